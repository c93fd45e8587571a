//! The interface between the host and the shaders, named once: every descriptor binding
//! ([`bindings`]), specialization constant ([`specialization`]), `DrawConstants::flags` bit
//! ([`flags`]) and per-mesh slot of the pre-pass's indirect buffers ([`slots`]).
//!
//! Each name has a GLSL twin written by hand where the shaders read it (the bindings in
//! `glsl/include/bindings.glsl` and the stages of the other layouts, the constants' ids where
//! each is declared, the flags in `glsl/include/types.glsl`, the slots in `bindings.glsl`).
//! `tests/layout.rs` reads the twins back — the bindings and specialization ids out of every
//! embedded SPIR-V module, the folded flag and slot constants out of the GLSL source — and fails
//! on any difference, so that two buffers swapped on one side only cannot pass unseen.

pub mod bindings;
pub mod flags;
pub mod slots;
pub mod specialization;

/// Declares `u32` constants and `ALL`, the table of their names and values (for the test that
/// compares them with their GLSL twins of the same names).
macro_rules! named_constants {
    ($($(#[$doc:meta])* $name:ident = $value:expr;)*) => {
        $($(#[$doc])* pub const $name: u32 = $value;)*

        /// Every constant of this module: its name (that of its GLSL twin) and its value.
        pub const ALL: &[(&str, u32)] = &[$((stringify!($name), $name)),*];
    };
}
pub(crate) use named_constants;

#[cfg(test)]
mod tests;
