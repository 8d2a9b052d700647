//! Strength of the response.

use super::*;

/// The same square (40 on 200) growing from half size 2 to 18 px at 0.5, 1, 1.5 and 2
/// px/frame: the faster the approach, the larger the peak `ΣLPLC2` and the larger `ΣLPLC2`
/// when the square passes half size 10.
#[test]
fn a_faster_approach_gives_a_larger_response() {
    let bg = Canvas::plain(200.0);
    let mut last = (0, 0);
    for rate in [0.5, 1.0, 1.5, 2.0] {
        let obj = Looming::square(49.0, 36.0, rate, 40.0);
        let n = (16.0 / rate) as usize;
        let outs = run(&looming_scene(&bg, &[obj], n));
        let peak = outs.iter().map(|o| o.vm.lplc2_sum).max().unwrap();
        let at10 = outs[(LEAD..outs.len()).find(|&t| obj.half(t) >= 10.0).unwrap()]
            .vm
            .lplc2_sum;
        report(&format!("approach at {rate} px/frame"), &outs);
        println!("  peak ΣLPLC2 {peak}, ΣLPLC2 at half size 10: {at10}");
        assert!(
            peak > last.0 && at10 > last.1,
            "{rate} px/frame: {peak} {at10} after {last:?}"
        );
        last = (peak, at10);
    }
}

/// At a constant 1 px/frame, `ΣLPLC2` grows with the square's size (never falls, and is
/// several times larger at half size 17 than at 4), and grows with contrast.
#[test]
fn the_response_grows_with_size_and_contrast() {
    let bg = Canvas::plain(200.0);
    let mut peaks = Vec::new();
    for grey in [100.0, 40.0] {
        let obj = Looming::square(49.0, 36.0, 1.0, grey);
        let outs = run(&looming_scene(&bg, &[obj], 16));
        let sums: Vec<u32> = outs[LEAD + 1..].iter().map(|o| o.vm.lplc2_sum).collect();
        report(&format!("square of grey {grey} on 200"), &outs);
        println!("  ΣLPLC2 per frame: {sums:?}");
        assert!(sums.windows(2).all(|w| w[1] >= w[0]), "{sums:?}");
        assert!(sums[sums.len() - 1] > 4 * sums[1], "{sums:?}");
        peaks.push(sums[sums.len() - 1]);
    }
    assert!(peaks[1] > peaks[0], "contrast 160 vs 100: {peaks:?}");
}
