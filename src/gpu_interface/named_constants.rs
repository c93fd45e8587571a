//! The macro that declares a module's named `u32` constants and their table, for the test that
//! compares them with their GLSL twins of the same names.

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
