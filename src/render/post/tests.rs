//! Tests of `render::post`: the adaptation weight and the push constants' size.

use super::*;

#[test]
fn adaptation_weight_follows_its_time_constant() {
    let settings = PostSettings::default();
    assert_eq!(Adapt::AtOnce.weight(&settings), 1.0);
    let one_constant = Adapt::After(settings.adaptation_seconds).weight(&settings);
    assert!((one_constant - (1.0 - (-1.0f32).exp())).abs() < 1e-6);
    assert_eq!(Adapt::After(0.0).weight(&settings), 0.0);
    assert!(Adapt::After(1.0 / 60.0).weight(&settings) < 0.05);
    assert_eq!(Adapt::After(f32::NAN).weight(&settings), 1.0);
    assert_eq!(Adapt::After(1e9).weight(&settings), 1.0);
}

#[test]
fn the_constants_are_the_eight_floats_of_post_glsl() {
    assert_eq!(std::mem::size_of::<PostConstants>(), 32);
}
