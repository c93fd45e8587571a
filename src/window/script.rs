//! The viewer's scripts: key presses, resizes, minimising and memory samples at given turns
//! of the loop, so that the viewer runs without a person; [`ViewScript::soak`] builds the long
//! one that `multirate soak` runs and tests/window.rs checks.

/// One scripted action.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScriptEvent {
    /// A key press, by the text it types ("p", "+", "[", "<", ...).
    Key(&'static str),
    /// Asks the window system for this inner size (X servers refuse a zero side: minimise
    /// instead).
    Resize(u32, u32),
    /// Minimises the window (where a window manager does so) and hands the viewer the
    /// zero-sized `Resized` event a minimised window gets on other systems: X servers keep an
    /// iconified window's size and refuse a zero-sized one, and Xvfb has no window manager.
    Minimise,
    /// Restores the window, and hands the viewer `Resized` with the window's size.
    Restore,
    /// Takes the memory figures ([`MemoryUse`]) into [`ViewReport::memory`].
    SampleMemory,
}

impl ScriptEvent {
    /// A short name for counting: "key p", "resize", "minimise", "restore", "sample memory".
    pub(super) fn kind(&self) -> String {
        match self {
            ScriptEvent::Key(key) => format!("key {key}"),
            ScriptEvent::Resize(..) => "resize".into(),
            ScriptEvent::Minimise => "minimise".into(),
            ScriptEvent::Restore => "restore".into(),
            ScriptEvent::SampleMemory => "sample memory".into(),
        }
    }
}

/// Scripted actions for automated runs, at turns of the loop (one per redraw, whether it
/// presents a frame or not, so that a minimised window's turns count too), and the frame to
/// close at.
#[derive(Clone, Debug, Default)]
pub struct ViewScript {
    /// (turn, event), in turn order; events of one turn run in list order after its redraw.
    pub events: Vec<(u32, ScriptEvent)>,
    /// The window closes once this many frames were presented.
    pub close_at_frame: u32,
}

/// The keys one soak cycle presses, in order, one every [`SOAK_STEP`] turns, with the window
/// events between them: every mode, N up and down, ε and n_max halved and doubled, the
/// estimator both ways, the heat map and the wireframe on and off, three sizes and a
/// minimised spell. A cycle ends in the state it started in (once n_max is off its clamp).
const SOAK_CYCLE: &[SoakStep] = &[
    SoakStep::Key("p"),
    SoakStep::Key("d"),
    SoakStep::Key("v"),
    SoakStep::Key("f"),
    SoakStep::Key("+"),
    SoakStep::Key("-"),
    SoakStep::Key("-"),
    SoakStep::Key("+"),
    SoakStep::Key("m"),
    SoakStep::Key("["),
    SoakStep::Key("]"),
    SoakStep::Key("]"),
    SoakStep::Key("["),
    SoakStep::Key("<"),
    SoakStep::Key(">"),
    SoakStep::Key(">"),
    SoakStep::Key("<"),
    SoakStep::Key("e"),
    SoakStep::Key("h"),
    SoakStep::Key("w"),
    SoakStep::Key("t"),
    SoakStep::Key("o"),
    SoakStep::Larger,
    SoakStep::Key("d"),
    SoakStep::Key("m"),
    SoakStep::Key("h"),
    SoakStep::Key("w"),
    SoakStep::Key("e"),
    SoakStep::Key("o"),
    SoakStep::Smallest,
    SoakStep::Key("f"),
    SoakStep::Key("m"),
    SoakStep::Initial,
    SoakStep::Minimise,
    SoakStep::Restore,
];

/// Turns between two steps of a soak cycle.
pub const SOAK_STEP: u32 = 4;

/// A step of [`SOAK_CYCLE`].
#[derive(Clone, Copy)]
enum SoakStep {
    Key(&'static str),
    /// The initial size × 3/2.
    Larger,
    /// 1 × 1.
    Smallest,
    Initial,
    Minimise,
    Restore,
}

impl ViewScript {
    /// A soak of at least `frames` presented frames in a window of `size`: `SOAK_CYCLE`
    /// repeated. The first cycle warms up (it builds every pipeline on first use and fills the
    /// caches); memory is sampled at the end of each cycle, so that the first sample follows
    /// a visit to every mode and all samples are taken in the same state.
    pub fn soak(frames: u32, size: (u32, u32)) -> ViewScript {
        let cycle_turns = SOAK_CYCLE.len() as u32 * SOAK_STEP;
        let minimised_turns = SOAK_STEP; // from Minimise to Restore
        let presented_per_cycle = cycle_turns - minimised_turns;
        // One cycle to warm up, and one more than needed for the turns a resize may cost (an
        // out-of-date swapchain skips a frame).
        let cycles = 2 + frames.div_ceil(presented_per_cycle);
        let larger = (size.0 + size.0 / 2, size.1 + size.1 / 2);
        let mut events = Vec::new();
        for cycle in 0..cycles {
            let base = cycle * cycle_turns;
            for (index, step) in SOAK_CYCLE.iter().enumerate() {
                let event = match *step {
                    SoakStep::Key(key) => ScriptEvent::Key(key),
                    SoakStep::Larger => ScriptEvent::Resize(larger.0, larger.1),
                    SoakStep::Smallest => ScriptEvent::Resize(1, 1),
                    SoakStep::Initial => ScriptEvent::Resize(size.0, size.1),
                    SoakStep::Minimise => ScriptEvent::Minimise,
                    SoakStep::Restore => ScriptEvent::Restore,
                };
                events.push((base + index as u32 * SOAK_STEP, event));
            }
            events.push((base + cycle_turns - 1, ScriptEvent::SampleMemory));
        }
        ViewScript { events, close_at_frame: frames }
    }
}

#[cfg(test)]
mod tests;
