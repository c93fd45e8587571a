//! A small seeded xorshift generator shared by the unit tests.

use glam::Vec3;

/// xorshift64: deterministic pseudo-random numbers; the seed must not be 0.
pub(crate) struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 40) as f32) / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f()
    }

    /// Uniform in 0..n.
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.f() * n as f32) as u32).min(n - 1)
    }

    /// A uniform byte.
    pub fn byte(&mut self) -> u8 {
        self.below(256) as u8
    }

    /// Uniform in the box [lo, hi).
    pub fn point(&mut self, lo: Vec3, hi: Vec3) -> Vec3 {
        Vec3::new(self.range(lo.x, hi.x), self.range(lo.y, hi.y), self.range(lo.z, hi.z))
    }
}
