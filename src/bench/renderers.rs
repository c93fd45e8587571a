//! The renderers one scene's configurations are drawn with. A renderer keeps one ball of eyes
//! and its held levels (`render::level_ball`, `render::level_hold`) for the multirate
//! configuration that drew last: a frame in other settings begins a fresh ball. Configurations
//! that took turns on one renderer would restart each other's ball and clear each other's held
//! levels at every turn, and be timed and measured as no user sees them; so every multirate
//! configuration after the first has a renderer of its own. The other modes keep nothing from
//! frame to frame and share the first renderer.

use crate::error::Result;
use crate::render::{Mode, Renderer};
use crate::scene::Scene;
use crate::vk::Context;
use std::sync::Arc;

/// The renderers of every multirate configuration after the first, by configuration (none for
/// the others).
pub struct OwnRenderers(Vec<Option<Renderer>>);

impl OwnRenderers {
    /// Renderers of `scene` for the configurations, of these `modes`, that need one of their own.
    pub fn new(
        context: &Arc<Context>,
        scene: &Scene,
        modes: impl IntoIterator<Item = Mode>,
    ) -> Result<OwnRenderers> {
        let mut multirate_before = false;
        let mut own = Vec::new();
        for mode in modes {
            let multirate = mode == Mode::Multirate;
            let needs_own = multirate && std::mem::replace(&mut multirate_before, true);
            own.push(if needs_own { Some(Renderer::new(context, scene)?) } else { None });
        }
        Ok(OwnRenderers(own))
    }

    /// The renderer configuration `index` is drawn with, where the others use `shared`.
    pub fn of<'a>(&'a self, shared: &'a Renderer, index: usize) -> &'a Renderer {
        self.0.get(index).and_then(Option::as_ref).unwrap_or(shared)
    }
}
