//! The output invariants: `check`, every documented bound and relation of one output.

use super::*;
use alvs_tasks::model::lplc2::uncut_response;

/// `a` and `b` are the same angle up to `tol` degrees.
fn same_angle(a: f32, b: f32, tol: f32) -> bool {
    let d = (a - b).rem_euclid(360.0);
    d <= tol || d >= 360.0 - tol
}

fn in_half_open_circle(a: f32) -> bool {
    a.is_finite() && a > -180.0 && a <= 180.0
}

/// ΣLPLC2 of `out`'s fields with each one a side border cuts counted at its whole width
/// (`Params::short_uncut`, [`uncut_response`]).
pub(crate) fn uncut_sum(out: &Perception, r_af: u8) -> u32 {
    out.afs.iter().fold(0u32, |acc, a| {
        acc.saturating_add(uncut_response(a.lplc2, a.x.into(), r_af))
    })
}

/// Every documented bound and relation of one output, for the `index`-th frame.
pub(crate) fn check(
    p: &Params,
    index: usize,
    out: &Perception,
    driving: bool,
) -> Result<(), TestCaseError> {
    let vm = &out.vm;
    let ctx = || format!("frame {index}: {out:?}");
    prop_assert_eq!(out.frame as usize, index);
    prop_assert!(
        out.afs.len() <= usize::from(p.firmware.max_fields),
        "{}",
        ctx()
    );
    if index == 0 {
        // the priming frame never alerts (its `strength` is not a sigmoid value: see the report)
        prop_assert!(
            out.afs.is_empty() && !out.alert() && vm.lplc2_sum == 0,
            "{}",
            ctx()
        );
        prop_assert!(
            vm.threat_x.is_none() && vm.theta_long.is_none(),
            "{}",
            ctx()
        );
        return Ok(());
    }
    // `Params::band_row`: driving, no field centred above the band responds
    if driving {
        prop_assert!(
            out.afs
                .iter()
                .all(|a| a.y >= off0(p.efference.band_row) || a.lplc2 == 0),
            "{}",
            ctx()
        );
    }
    let mut ids: Vec<u32> = out.afs.iter().map(|a| a.id).collect();
    ids.sort_unstable();
    ids.dedup();
    prop_assert_eq!(ids.len(), out.afs.len(), "duplicate ids: {}", ctx());
    for af in &out.afs {
        prop_assert!(
            usize::from(af.x) < WIDTH && usize::from(af.y) < HEIGHT,
            "{}",
            ctx()
        );
        prop_assert!(af.age >= 1, "{}", ctx());
        // Eq. (9): zero, or the (saturating) sum of four quadrants, at least `q_arms` of them
        // above the floor (all four with the paper's gate); with `t_lplc2`, zero or a mean
        // over frames above it
        let sum = af.quadrants.iter().fold(0u32, |a, &q| a.saturating_add(q));
        if off0(p.firmware.t_lplc2) > 0 {
            prop_assert!(
                af.lplc2 == 0 || af.lplc2 > off0(p.firmware.t_lplc2),
                "{}",
                ctx()
            );
        } else {
            prop_assert!(af.lplc2 == 0 || af.lplc2 == sum, "{}", ctx());
        }
        if af.lplc2 > 0 && off0(p.firmware.t_lplc2) == 0 {
            let excited = af
                .quadrants
                .iter()
                .filter(|&&q| q > p.choices.q_floor)
                .count();
            prop_assert!(excited >= usize::from(p.choices.q_arms), "{}", ctx());
        }
    }
    let total = out.afs.iter().fold(0u32, |a, f| a.saturating_add(f.lplc2));
    prop_assert_eq!(vm.lplc2_sum, total, "{}", ctx());
    prop_assert_eq!(out.alert(), vm.alert);
    prop_assert_eq!(out.short_mode(), vm.short_mode);
    // an alert comes from the fields, or else from the floor line of a driving robot
    let floor_alert = vm.alert && vm.lplc2_sum == 0;
    prop_assert!(
        !floor_alert || (driving && off0(p.efference.floor_row) > 0 && !vm.short_mode),
        "{}",
        ctx()
    );
    prop_assert!(vm.alert || vm.lplc2_sum == 0, "{}", ctx());
    // the floor line reports only for a driving robot
    prop_assert!(
        vm.obstacle.is_none() || (driving && off0(p.efference.floor_row) > 0),
        "{}",
        ctx()
    );
    // alone, its saccade is the θ¹ of the threat it reports
    if vm.alert && vm.lplc2_sum == 0 {
        prop_assert_eq!(vm.obstacle, vm.theta_short.map(|[t1, _]| t1), "{}", ctx());
    }
    let in_path = |x: f32| (x - 49.0).abs() <= f32::from(off0(p.short.short_cols));
    let off_path = driving && off0(p.short.short_cols) > 0 && !vm.threat_x.is_some_and(in_path);
    // a driving robot's threat whose foot is far (`Params::short_row`) is not imminent either
    let far_gate = driving && off0(p.short.short_row) > 0;
    // the short mode's test: ΣLPLC2 above `T_s`, or, standing with `Params::short_uncut`, the
    // sum with the fields a side border cuts counted whole, or, standing with
    // `Params::short_young`, an alert in a field's first `d` frames after the warm-up
    let over = vm.lplc2_sum > p.table1.t_s
        || (p.short.short_uncut && !driving && uncut_sum(out, p.table1.r_af) > p.table1.t_s)
        || (p.short.short_young
            && !driving
            && out.afs.iter().any(|f| f.alerts_young(out.frame, p)));
    if off0(p.short.adapt_frames) == 0 && !off_path && !far_gate {
        prop_assert_eq!(vm.short_mode, over, "{}", ctx());
    } else {
        // motion adaptation, a threat off the path of a driving robot (`Params::short_cols`)
        // and one far ahead of it (`Params::short_row`) can only hold the short mode back
        prop_assert!(!vm.short_mode || over, "{}", ctx());
        prop_assert!(!vm.short_mode || !off_path, "{}", ctx());
    }
    prop_assert!(!vm.short_mode || vm.alert, "{}", ctx());
    prop_assert!(
        vm.strength.is_finite() && (0.5..=1.0).contains(&vm.strength),
        "{}",
        ctx()
    );
    prop_assert_eq!(vm.threat_x.is_some(), vm.alert, "{}", ctx());
    prop_assert_eq!(vm.theta_long.is_some(), vm.alert, "{}", ctx());
    prop_assert_eq!(vm.theta_short.is_some(), vm.alert, "{}", ctx());
    if let Some(x) = vm.threat_x {
        prop_assert!(x.is_finite(), "{}", ctx());
        // On the retina, and a weighted mean of the stimulated fields' columns, even when
        // ΣLPLC2 saturates (see `threat_centroid_survives_saturated_responses`); the floor
        // line's column when it alone alerts.
        prop_assert!((0.0..=98.0).contains(&x), "{}", ctx());
        if !floor_alert {
            let xs = out
                .afs
                .iter()
                .filter(|a| a.lplc2 > 0)
                .map(|a| f32::from(a.x));
            let lo = xs.clone().fold(f32::INFINITY, f32::min);
            let hi = xs.fold(f32::NEG_INFINITY, f32::max);
            prop_assert!(x >= lo - 1e-3 && x <= hi + 1e-3, "{}", ctx());
        }
        // Eq. (13): turn to face away from the threat
        let long = vm.theta_long.unwrap();
        prop_assert!(in_half_open_circle(long), "{}", ctx());
        let expect = p.table1.alpha * (x - 49.0) + 180.0;
        prop_assert!(
            same_angle(long, expect, 1e-2),
            "{} vs {}: {}",
            long,
            expect,
            ctx()
        );
        // Eqs. (14)–(15): the second heading is 90° further than the first, same direction
        let [s1, s2] = vm.theta_short.unwrap();
        prop_assert!(
            in_half_open_circle(s1) && in_half_open_circle(s2),
            "{}",
            ctx()
        );
        prop_assert!(
            same_angle(s2 - s1, 90.0, 1e-2) || same_angle(s2 - s1, -90.0, 1e-2),
            "{}",
            ctx()
        );
    }
    Ok(())
}
