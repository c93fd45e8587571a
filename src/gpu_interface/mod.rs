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
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`named_constants`]: the macro that declares named constants with the table of their names.
//! 2. [`bindings`]: every descriptor binding of every layout.
//! 3. [`flags`]: the bits of `DrawConstants::flags`.
//! 4. [`slots`]: the per-mesh slots of the pre-pass's indirect buffers.
//! 5. [`specialization`]: the specialization constants' ids.

pub mod bindings;
pub mod flags;
mod named_constants;
pub mod slots;
pub mod specialization;

#[cfg(test)]
mod tests;
