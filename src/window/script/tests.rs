//! Tests of `window::script`: the soak script cycles every key, size and minimised spell.

use super::*;

#[test]
fn the_soak_script_cycles_every_key_size_and_minimised_spell() {
    let script = ViewScript::soak(10_000, (64, 48));
    assert_eq!(script.close_at_frame, 10_000);
    assert!(script.events.windows(2).all(|pair| pair[0].0 <= pair[1].0), "in turn order");
    let count = |wanted: ScriptEvent| script.events.iter().filter(|(_, e)| *e == wanted).count();
    let cycles = count(ScriptEvent::SampleMemory);
    let presented_per_cycle = (SOAK_CYCLE.len() - 1) * SOAK_STEP as usize;
    assert!((cycles - 2) * presented_per_cycle >= 10_000, "enough cycles: {cycles}");
    for key in ["p", "d", "v", "f", "m", "e", "h", "w", "t", "+", "-", "[", "]", "<", ">"] {
        assert!(count(ScriptEvent::Key(key)) >= cycles, "{key}");
    }
    assert_eq!(count(ScriptEvent::Resize(96, 72)), cycles);
    assert_eq!(count(ScriptEvent::Resize(1, 1)), cycles);
    assert_eq!(count(ScriptEvent::Resize(64, 48)), cycles);
    assert_eq!(count(ScriptEvent::Minimise), cycles);
    // Each minimised spell ends in a restore before anything else happens.
    for (index, (turn, event)) in script.events.iter().enumerate() {
        if *event == ScriptEvent::Minimise {
            assert_eq!(script.events[index + 1], (turn + SOAK_STEP, ScriptEvent::Restore));
        }
    }
}
