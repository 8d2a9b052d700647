//! The transition table: every state, every kind of input.

use super::*;

#[test]
fn transition_table_covers_every_state() {
    const H: f32 = 20.0;
    // (description, FSM in the start state, input, heading of the frame, next state, next phase)
    type Row = (
        &'static str,
        Fsm,
        Visuomotor,
        f32,
        State,
        Option<ShortPhase>,
    );
    let retreat = Some(ShortPhase::Retreat);
    let turn = Some(ShortPhase::Turn);
    let mut rows: Vec<Row> = vec![
        (
            "wander, none",
            in_wander(H),
            quiet(),
            H,
            State::Wander,
            None,
        ),
        (
            "wander, alert",
            in_wander(H),
            long(LEFT_X),
            H,
            State::LongTakeoff,
            None,
        ),
        (
            "wander, short",
            in_wander(H),
            short(LEFT_X),
            H,
            State::ShortTakeoff,
            retreat,
        ),
    ];
    let (f, _) = in_long(H);
    rows.push((
        "long, none, not aligned",
        f,
        quiet(),
        H,
        State::LongTakeoff,
        None,
    ));
    let (f, _) = in_long(H);
    rows.push((
        "long, alert, not aligned (alerts do not interrupt the turn)",
        f,
        long(LEFT_X),
        H,
        State::LongTakeoff,
        None,
    ));
    let (f, sp) = in_long(H);
    rows.push(("long, none, aligned", f, quiet(), sp, State::Escape, None));
    let (f, sp) = in_long(H);
    rows.push((
        "long, none, within tolerance",
        f,
        quiet(),
        sp + 0.9 * tol(),
        State::Escape,
        None,
    ));
    let (f, sp) = in_long(H);
    rows.push((
        "long, none, just outside tolerance",
        f,
        quiet(),
        sp + 1.1 * tol(),
        State::LongTakeoff,
        None,
    ));
    let (f, _) = in_long(H);
    rows.push((
        "long, short",
        f,
        short(LEFT_X),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_escape(H);
    rows.push(("escape early, none", f, quiet(), sp, State::Escape, None));
    let (f, sp) = in_escape(H);
    rows.push((
        "escape early, alert (minimum duration)",
        f,
        long(LEFT_X),
        sp,
        State::Escape,
        None,
    ));
    let (f, sp) = in_escape(H);
    rows.push((
        "escape early, short",
        f,
        short(LEFT_X),
        sp,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_escape_late(H);
    rows.push((
        "escape late, alert",
        f,
        long(LEFT_X),
        sp,
        State::LongTakeoff,
        None,
    ));
    let (f, sp) = in_escape_late(H);
    rows.push((
        "escape late, none, not yet quiet",
        f,
        quiet(),
        sp,
        State::Escape,
        None,
    ));
    let (f, _) = in_short(H);
    rows.push((
        "short retreat, none, not aligned",
        f,
        quiet(),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_short(H);
    rows.push((
        "short retreat, none, aligned with sp1",
        f,
        quiet(),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, _) = in_short(H);
    rows.push((
        "short retreat, short again (no re-latch)",
        f,
        short(LEFT_X),
        H,
        State::ShortTakeoff,
        retreat,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, none, not aligned",
        f,
        quiet(),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, alert, not aligned",
        f,
        long(LEFT_X),
        sp[0],
        State::ShortTakeoff,
        turn,
    ));
    let (f, sp) = in_short_turn(H);
    rows.push((
        "short turn, none, aligned with sp2",
        f,
        quiet(),
        sp[1],
        State::Escape,
        None,
    ));
    rows.push((
        "swarm wander, none",
        swarm_wander(H),
        quiet(),
        H,
        State::Wander,
        None,
    ));
    rows.push((
        "swarm wander, alert",
        swarm_wander(H),
        long(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm wander, short",
        swarm_wander(H),
        short(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, none",
        swarm_spin(H),
        quiet(),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, alert",
        swarm_spin(H),
        long(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm spin, short",
        swarm_spin(H),
        short(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm look, none",
        swarm_look(H),
        quiet(),
        H,
        State::Look,
        None,
    ));
    rows.push((
        "swarm look, alert",
        swarm_look(H),
        long(RIGHT_X),
        H,
        State::Spin,
        None,
    ));
    rows.push((
        "swarm look, a mover",
        swarm_look(H),
        saw(Sighting::Mover { x: RIGHT_X }),
        H,
        State::Wander,
        None,
    ));
    rows.push((
        "swarm look, nothing",
        swarm_look(H),
        saw(Sighting::Nothing),
        H,
        State::Look,
        None,
    ));

    rows.push(("stop, none", in_stop(H), quiet(), H, State::Stop, None));
    rows.push((
        "stop, alert",
        in_stop(H),
        long(LEFT_X),
        H,
        State::LongTakeoff,
        None,
    ));
    rows.push((
        "stop, short (the paper's override of every state)",
        in_stop(H),
        short(LEFT_X),
        H,
        State::ShortTakeoff,
        retreat,
    ));

    let mut seen = [false; 7];
    for (what, mut f, vm, h, next, phase) in rows {
        seen[f.state() as usize] = true;
        let c = f.step(&vm, h);
        assert_eq!((c.state, c.short_phase), (next, phase), "{what}");
        assert_eq!(f.state(), next, "{what}");
        assert_eq!(f.short_phase(), phase, "{what}");
    }
    assert!(seen.iter().all(|&s| s), "every state is a start state");
}
