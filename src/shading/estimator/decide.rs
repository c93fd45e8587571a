//! From the summed bounds to the level: [`decide`] (the Heuristic and Uniform splits and the
//! grid), [`level_for`] and the predicted error ([`bound_at`]).
//!
//! GLSL twin: `glsl/include/estimator/decide.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::UNIFORM_TINY;
use super::light_setup::{Sums, GRID_LEVELS};
use super::patch_levels::{pattern_level, uniform_level, FALLBACK_LEVEL};
use super::settings::Split;
use super::terms::{Estimate, Reason, Term, TERM_COUNT};
use glam::Vec3;

/// Smallest real `n > 0` with `a/n² + b/n + c ≤ eps` (`∞` if none).
pub(super) fn level_for(a: f32, b: f32, c: f32, eps: f32) -> f32 {
    if a <= 0.0 && b <= 0.0 {
        return if c <= eps { 0.0 } else { f32::INFINITY };
    }
    let room = eps - c;
    if !(room > 0.0) {
        return f32::INFINITY;
    }
    let n = (b + (b * b + 4.0 * a * room).sqrt()) / (2.0 * room);
    if n.is_nan() {
        f32::INFINITY
    } else {
        n
    }
}

/// The bound on the uniform pattern at level `n`: per channel the smallest that holds there of
/// the level-1 bound (`n = 1`), the grid's bound (`n` on [`GRID_LEVELS`]) and the bound for
/// sub-triangles of radius² `K/L²`, `L = pattern_level(n, n)` (from [`Sums::low`] on);
/// `f32::MAX` if none does.
pub(super) fn bound_at(sum: &Sums, an: Vec3, n: u32) -> f32 {
    let l = pattern_level(n, n);
    let mut e = if l >= sum.low {
        an / (l * l) + sum.linn / l + sum.jumps + sum.range
    } else {
        Vec3::splat(f32::INFINITY)
    };
    if n <= 1 {
        e = e.min(sum.one);
    }
    if let Some(k) = GRID_LEVELS.iter().position(|&g| g == n) {
        e = e.min(sum.grid[k]);
    }
    let m = e.max_element();
    if m.is_nan() {
        f32::MAX
    } else {
        m.min(f32::MAX)
    }
}

pub(super) fn decide(sum: &Sums, eps: f32, n_max: u32, split: Split, reason: Reason) -> Estimate {
    let an = sum.tn;
    let finite = |x: f32| {
        if x.is_nan() {
            f32::MAX
        } else {
            x.min(f32::MAX)
        }
    };

    let mut terms = [0.0f32; TERM_COUNT];
    for (t, out) in terms.iter_mut().enumerate() {
        let b = sum.hn[t].max_element();
        if b > 0.0 {
            *out = finite((b / eps).sqrt());
        }
    }
    let jumps = sum.jumps;
    let zero = sum.jumps + sum.range;
    let relaxed_on = sum.linn.max_element() > 0.0 || jumps.max_element() > 0.0;
    if relaxed_on {
        let mut worst = 0.0f32;
        for c in 0..3 {
            worst = worst.max(level_for(0.0, sum.linn[c], jumps[c], eps));
        }
        terms[Term::Terminator as usize] = finite(worst);
    }
    let range_on = sum.range.max_element() > 0.0;
    if range_on {
        terms[Term::Range as usize] = if sum.range.max_element() <= eps { 0.0 } else { f32::MAX };
    }

    // `one_ok`: the level-1 bound holds, and then it holds for every pattern (each of
    // whose sub-triangles lies inside the patch). `need`: the smallest effective level `L`
    // at which the bound for sub-triangles of radius² `K/L²` and diameter `D/L` holds.
    let (one_ok, need) = match split {
        Split::Heuristic => {
            let mut n = 0.0f32;
            for c in 0..3 {
                n = n.max(level_for(an[c], sum.linn[c], zero[c], eps));
            }
            (sum.one.max_element() <= eps, n)
        }
        Split::Uniform => {
            // M counts the terms above ε·UNIFORM_TINY; the others share a reserve.
            let tiny = eps * UNIFORM_TINY;
            let mut count = 0u32;
            for t in 0..TERM_COUNT {
                if sum.hn[t].max_element() > tiny || sum.h1[t].max_element() > tiny {
                    count += 1;
                }
            }
            if sum.linn.max_element() > tiny || jumps.max_element() > tiny || sum.jumps1.max_element() > tiny
            {
                count += 1;
            }
            if sum.range.max_element() > tiny {
                count += 1;
            }
            let share = eps * (1.0 - 16.0 * UNIFORM_TINY) / count.max(1) as f32;
            let one_ok = (0..TERM_COUNT).all(|t| sum.h1[t].max_element() <= share)
                && (sum.lin1 + sum.jumps1).max_element() <= share
                && sum.range.max_element() <= share;
            let mut n = 0.0f32;
            for t in 0..TERM_COUNT {
                for c in 0..3 {
                    n = n.max(level_for(sum.hn[t][c], 0.0, 0.0, share));
                }
            }
            if relaxed_on {
                for c in 0..3 {
                    n = n.max(level_for(0.0, sum.linn[c], jumps[c], share));
                }
            }
            if sum.range.max_element() > share {
                n = f32::INFINITY;
            }
            (one_ok, n)
        }
    };
    let mut level = if one_ok { 1.0 } else { need.max(1.0) };
    // Heuristic: the lowest grid level whose bound, each part at its better bound there,
    // holds (it holds at every higher effective level too: both bounds only fall).
    if split == Split::Heuristic && !one_ok {
        for (k, &n) in GRID_LEVELS.iter().enumerate() {
            if n > n_max {
                break;
            }
            if sum.grid[k].max_element() <= eps {
                level = level.min(pattern_level(n, n));
                break;
            }
        }
    }

    let mut reason = reason;
    // false for NaN and ∞
    if reason == Reason::None && !(level <= pattern_level(n_max, n_max)) {
        reason = Reason::Level;
    }
    match reason {
        Reason::None => {
            let n = uniform_level(level, n_max);
            Estimate {
                terms,
                level,
                n,
                fallback: false,
                reason,
                predicted_error: bound_at(sum, an, n),
                refined: false,
            }
        }
        Reason::Level => Estimate {
            terms,
            level: FALLBACK_LEVEL,
            n: 1,
            fallback: true,
            reason,
            predicted_error: bound_at(sum, an, n_max),
            refined: false,
        },
        Reason::Discontinuity | Reason::Singular => Estimate {
            terms,
            level: FALLBACK_LEVEL,
            n: 1,
            fallback: true,
            reason,
            predicted_error: f32::MAX,
            refined: false,
        },
    }
}
