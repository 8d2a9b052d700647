//! Running and reporting.

use super::*;

/// Runs the frames through a fresh network with `Params::default()`.
pub(crate) fn run(frames: &[Frame]) -> Vec<Perception> {
    run_with(Params::default(), frames)
}

/// Runs the frames through a fresh network with `params`.
pub(crate) fn run_with(params: Params, frames: &[Frame]) -> Vec<Perception> {
    let mut net = Network::new(params).unwrap();
    frames.iter().map(|f| net.step(f)).collect()
}

pub(crate) fn alerts(outs: &[Perception]) -> usize {
    outs.iter().filter(|o| o.alert()).count()
}

/// Prints one line per scene: alerts, AFs, peak `ΣLPLC2` and the mean `X̄` of alert frames.
pub(crate) fn report(name: &str, outs: &[Perception]) -> usize {
    let xs: Vec<f32> = outs.iter().filter_map(|o| o.vm.threat_x).collect();
    let mean_x = (!xs.is_empty()).then(|| xs.iter().sum::<f32>() / xs.len() as f32);
    let n = alerts(outs);
    println!(
        "{name}: alerts {n}/{} | max AFs {} | peak ΣLPLC2 {} | mean X̄ {}",
        outs.len(),
        outs.iter().map(|o| o.afs.len()).max().unwrap_or(0),
        outs.iter().map(|o| o.vm.lplc2_sum).max().unwrap_or(0),
        mean_x.map_or("-".into(), |x| format!("{x:.1}")),
    );
    n
}

/// Runs many scenes that must never alert; prints each and fails listing those that did.
pub(crate) fn assert_never_alerts(scenes: impl IntoIterator<Item = (String, Vec<Frame>)>) {
    let (mut failed, mut total, mut count) = (Vec::new(), 0, 0);
    for (name, frames) in scenes {
        let outs = run(&frames);
        let n = report(&name, &outs);
        total += outs.len();
        count += 1;
        if n > 0 {
            failed.push(format!("{name}: {n}/{}", outs.len()));
        }
    }
    println!("{count} scenes, {total} frames, alerting: {failed:?}");
    assert!(failed.is_empty(), "alerts in: {failed:#?}");
}

/// The most stimulated field of a frame.
pub(crate) fn strongest(o: &Perception) -> Option<&alvs_tasks::AfReport> {
    o.afs.iter().max_by_key(|a| a.lplc2)
}

/// What one approaching object (`obj`, expanding for `n` frames after the lead) must produce:
/// silence while still, alerts on at least 2/3 of the expansion frames starting within 3
/// frames of the onset, and on every alert frame `X̄` and the strongest field within 6 px of
/// the object's centre, the escape turning away from the object's side, `S` and short mode
/// consistent with `ΣLPLC2` (or, the network standing, with a field alerting in its first `d`
/// frames, `Params::short_young`).
pub(crate) fn check_approach(name: &str, outs: &[Perception], obj: &Looming, n: usize) {
    report(name, outs);
    assert_eq!(alerts(&outs[..LEAD]), 0, "{name}: alert before the onset");
    let during = &outs[LEAD..LEAD + n];
    let first = during.iter().position(|o| o.alert());
    let count = alerts(during);
    println!("  first alert {first:?} frames after onset, {count}/{n} expansion frames alert");
    assert!(
        first.is_some_and(|k| k <= 2),
        "{name}: late onset {first:?}"
    );
    assert!(
        3 * count >= 2 * n,
        "{name}: only {count}/{n} expansion frames alert"
    );
    let p = Params::default();
    for o in outs.iter().filter(|o| o.alert()) {
        let vm = &o.vm;
        let x = vm.threat_x.expect("an alert has a threat centroid");
        let af = strongest(o).unwrap();
        let at = format!(
            "{name}, frame {}: X̄ {x}, AF ({}, {}), {vm:?}",
            o.frame, af.x, af.y
        );
        assert!((x - obj.cx).abs() <= 6.0, "{at}");
        assert!((f32::from(af.x) - obj.cx).abs() <= 6.0, "{at}");
        assert!((f32::from(af.y) - obj.cy).abs() <= 6.0, "{at}");
        let long = vm.theta_long.unwrap();
        let [s1, s2] = vm.theta_short.unwrap();
        if obj.cx < CENTRE - 10.0 {
            // threat on the left: turn right, ending 145°..180° away
            assert!(x < CENTRE && long > 145.0 && long <= 180.0, "{at}");
            assert!(s1 > 0.0 && s2 > 0.0, "{at}");
        } else if obj.cx > CENTRE + 10.0 {
            assert!(x > CENTRE && long < -145.0 && long > -180.0, "{at}");
            assert!(s1 < 0.0 && s2 < 0.0, "{at}");
        } else {
            // ahead: turn (almost) around; 10 px off centre is 7.07°
            assert!((x - CENTRE).abs() <= 10.0 && long.abs() >= 172.9, "{at}");
        }
        assert!(vm.strength > 0.5 && vm.strength <= 1.0, "{at}");
        let young = o.afs.iter().any(|a| a.alerts_young(o.frame, &p));
        let short = vm.lplc2_sum > p.table1.t_s || (p.short.short_young && young);
        assert_eq!(vm.short_mode, short, "{at}");
    }
}

/// Prints a scene frame by frame (for the reader of a failure).
pub(crate) fn trace(outs: &[Perception]) {
    for o in outs {
        let afs: Vec<String> = o
            .afs
            .iter()
            .map(|a| format!("#{}({},{}) L{}", a.id, a.x, a.y, a.lplc2))
            .collect();
        println!(
            "  frame {:3}: ΣLPLC2 {:6} X̄ {:5} | {}",
            o.frame,
            o.vm.lplc2_sum,
            o.vm.threat_x.map_or("-".into(), |x| format!("{x:.1}")),
            afs.join(" ")
        );
    }
}

pub(crate) const POSITIONS: [f32; 3] = [20.0, 49.0, 78.0];

/// How many of `scenes` alert at least once under `params`.
pub(crate) fn alerting_under(
    params: Params,
    scenes: impl IntoIterator<Item = (String, Vec<Frame>)>,
) -> usize {
    scenes
        .into_iter()
        .filter(|(_, frames)| alerts(&run_with(params, frames)) > 0)
        .count()
}
