//! Tests of the LPLC2 stage: the quadrants, the gate, and the row kernels held to the
//! pixel-by-pixel reference.

use super::*;
use crate::frame::{HEIGHT, PIXELS, WIDTH};
use crate::model::hrc::cells_of;
use crate::model::params::Params;
use crate::model::params::{Choices, TableOne};
use proptest::prelude::*;

#[test]
fn quadrants_follow_the_image_axes() {
    assert_eq!(quadrant_of(60, 10, 50, 30), Some(0)); // upper right
    assert_eq!(quadrant_of(40, 10, 50, 30), Some(1)); // upper left
    assert_eq!(quadrant_of(40, 50, 50, 30), Some(2)); // lower left
    assert_eq!(quadrant_of(60, 50, 50, 30), Some(3)); // lower right
    assert_eq!(quadrant_of(50, 10, 50, 30), None);
    assert_eq!(quadrant_of(60, 30, 50, 30), None);
}

fn g(floor: u32, balance: u8, arms: u8) -> Gate {
    Gate {
        floor,
        balance,
        arms,
    }
}

#[test]
fn gate_needs_all_four_arms_above_the_floor() {
    assert_eq!(gate([10, 20, 30, 40], &g(5, 0, 4)), 100);
    assert_eq!(gate([10, 20, 0, 40], &g(0, 0, 4)), 0);
    assert_eq!(gate([10, 20, 5, 40], &g(5, 0, 4)), 0);
    assert_eq!(gate([u32::MAX, 1, 1, 1], &g(0, 0, 4)), u32::MAX);
    // balance: every arm at least 25 % of the strongest
    assert_eq!(gate([10, 20, 30, 40], &g(5, 25, 4)), 100);
    assert_eq!(gate([9, 20, 30, 40], &g(5, 25, 4)), 0);
    assert_eq!(Gate::of(&Params::PAPER).arms, 4);
}

#[test]
fn gate_with_three_arms_lets_one_quadrant_be_quiet() {
    // one arm below the floor (the firmware's "3 of 4 expansion edges")
    assert_eq!(gate([10, 20, 5, 40], &g(5, 0, 3)), 75);
    // one below the balance
    assert_eq!(gate([9, 20, 30, 40], &g(5, 25, 3)), 99);
    // two quiet arms (translation floods two) still close it
    assert_eq!(gate([0, 20, 0, 40], &g(5, 0, 3)), 0);
    assert_eq!(gate([0, 20, 0, 40], &g(5, 0, 2)), 60);
}

/// A dark square's outline one pixel larger now than one frame earlier.
#[test]
fn the_side_borders_cut_a_field_within_half_its_half_side() {
    // R_AF 36: 18 columns or more on a side keep that side
    assert_eq!(cut_sides(17, 36, false), (true, false));
    assert_eq!(cut_sides(18, 36, false), (false, false));
    assert_eq!(cut_sides(49, 36, false), (false, false));
    assert_eq!(cut_sides(80, 36, false), (false, false));
    assert_eq!(cut_sides(81, 36, false), (false, true));
    // symmetric: columns in view on the cut side, 17 on both
    assert_eq!(cut_sides(WIDTH - 1 - 17, 36, false), (false, true));
    // a field wider than the retina is cut on both sides
    assert_eq!(cut_sides(49, 99, false), (true, true));
}

#[test]
fn with_border_crossing_a_side_is_cut_once_the_square_crosses_it() {
    // R_AF 36: the square of a field centred on column 35 reaches column -1
    assert_eq!(cut_sides(35, 36, true), (true, false));
    assert_eq!(cut_sides(36, 36, true), (false, false));
    assert_eq!(cut_sides(62, 36, true), (false, false));
    assert_eq!(cut_sides(63, 36, true), (false, true));
    // the half-side rule's cuts are kept: crossing only widens
    for cx in 0..WIDTH {
        let (l, r) = cut_sides(cx, 36, false);
        let (lc, rc) = cut_sides(cx, 36, true);
        assert!((!l || lc) && (!r || rc), "column {cx}");
    }
}

#[test]
fn a_blind_quadrant_counts_as_its_mirror_image() {
    let g = g(250, 15, 3);
    // a half-visible looming object at the left border: its inner edge moving right excites
    // the right quadrants, its bottom edge moving down the lower left one
    let half = [4_000, 100, 1_000, 3_500];
    assert_eq!(excited(half, &g), 3);
    let upper = [4_000, 100, 100, 100];
    assert_eq!(excited_at_border(upper, &g, (false, false)), 1);
    let looming = [4_000, 100, 1_000, 0];
    assert_eq!(excited(looming, &g), 2);
    // cut on the left: 1 takes 0's excitation, as 2 is excited by itself
    assert_eq!(excited_at_border(looming, &g, (true, false)), 3);
    // not cut: nothing is lent across the axis
    assert_eq!(excited_at_border(looming, &g, (false, false)), 2);
    // an object translating right past the left border excites only the right quadrants:
    // nothing on the cut side, nothing mirrored
    let translating = [4_000, 100, 100, 3_500];
    assert_eq!(excited_at_border(translating, &g, (true, false)), 2);
    // the same at the right border, moving left
    let leftwards = [100, 4_000, 3_500, 100];
    assert_eq!(excited_at_border(leftwards, &g, (false, true)), 2);
    assert_eq!(
        excited_at_border([1_000, 4_000, 3_500, 100], &g, (false, true)),
        4
    );
    assert_eq!(excited_at_border(half, &g, (true, false)), 4);
    // the balance is still the strongest real quadrant's: 500 is under 15 % of 4,000
    let weak = [4_000, 0, 500, 500];
    assert_eq!(excited_at_border(weak, &g, (true, false)), 1);
}

fn square_outline(half: usize, cx: usize, cy: usize) -> [u8; PIXELS] {
    let mut m = [0u8; PIXELS];
    for y in cy - half..=cy + half {
        for x in cx - half..=cx + half {
            if y == cy - half || y == cy + half || x == cx - half || x == cx + half {
                m[y * WIDTH + x] = 60;
            }
        }
    }
    m
}

#[test]
fn an_expanding_outline_excites_all_quadrants_and_a_shrinking_one_none() {
    let p = Params::default();
    let sc = LmScale::new(&p);
    let zero = [0u8; PIXELS];
    let small = square_outline(8, 50, 36);
    let large = square_outline(9, 50, 36);
    let cols = (14, 86);
    let rows = (0, 71);
    // OFF channel edges: expanding = small at t−1, large at t
    let grow = cells_of([&zero, &large, &zero, &small]);
    let grow = Maps::new(&grow);
    let l = integrate(&grow, &sc, (50, 36), cols, rows, &g(0, 0, 4));
    assert!(l.quadrants.iter().all(|&q| q > 0), "{:?}", l.quadrants);
    assert_eq!(l.quadrants[0], l.quadrants[2], "symmetric stimulus");
    assert_eq!(l.response, l.quadrants.iter().sum::<u32>());
    let shrink = cells_of([&zero, &small, &zero, &large]);
    let shrink = Maps::new(&shrink);
    let l = integrate(&shrink, &sc, (50, 36), cols, rows, &g(0, 0, 4));
    assert_eq!(l.quadrants, [0; 4]);
    assert_eq!(l.response, 0);
}

#[test]
fn one_pass_equals_per_field_integration() {
    let p = Params::default();
    let sc = LmScale::new(&p);
    // pseudo-random maps with plenty of motion in every direction
    let maps = crate::model::hrc::random_maps(12345);
    let cells = cells_of([&maps[0], &maps[1], &maps[2], &maps[3]]);
    let m = Maps::new(&cells);
    let regions = [
        Region {
            centre: (10, 10),
            cols: (0, 46),
            rows: (0, 46),
        },
        Region {
            centre: (60, 40),
            cols: (24, 96),
            rows: (4, 71),
        },
        Region {
            centre: (98, 0),
            cols: (62, 98),
            rows: (0, 36),
        },
    ];
    let mut all = [Lplc2::default(); 3];
    integrate_all(&m, &sc, &regions, &g(300, 15, 4), &mut all);
    for (r, got) in regions.iter().zip(all.iter()) {
        assert_eq!(
            *got,
            integrate(&m, &sc, r.centre, r.cols, r.rows, &g(300, 15, 4)),
            "{r:?}"
        );
    }
    // the corner field at (98, 0) has no upper or right quadrant; the others see motion
    assert!(all[..2].iter().all(|l| l.quadrants.iter().all(|&q| q > 0)));
    assert_eq!(all[2].quadrants[0], 0);
}

#[test]
fn the_paper_parameters_take_the_row_kernel() {
    let sc = LmScale::new(&Params::PAPER);
    let nw = Narrow::new(&sc).expect("narrow");
    assert_eq!((nw.a, nw.b, nw.shift, nw.n), (1, 16, 8, 3));
    // s > 1 and wide factors fall back to the general path
    let p = Params {
        choices: Choices {
            s: 2,
            ..Params::PAPER.choices
        },
        ..Params::PAPER
    };
    assert_eq!(Narrow::new(&LmScale::new(&p)), None);
    let p = Params {
        table1: TableOne {
            w: 4.0,
            ..Params::PAPER.table1
        },
        choices: Choices {
            gain: 16,
            lm_shift: 0,
            ..Params::PAPER.choices
        },
        ..Params::PAPER
    };
    assert_eq!(Narrow::new(&LmScale::new(&p)), None);
}

#[test]
fn short_bands_sum_as_long_ones() {
    // `Narrow::rows` caps the rows a band sums in `u32`; any cap gives the same quadrants
    let sc = LmScale::new(&Params::PAPER);
    let nw = Narrow::new(&sc).expect("narrow");
    assert_eq!(nw.rows, HEIGHT, "Table I sums a whole frame in u32");
    let maps = crate::model::hrc::random_maps(777);
    let cells = cells_of([&maps[0], &maps[1], &maps[2], &maps[3]]);
    let m = Maps::new(&cells);
    let regions = [
        Region {
            centre: (30, 20),
            cols: (5, 55),
            rows: (0, 45),
        },
        Region {
            centre: (50, 50),
            cols: (20, 80),
            rows: (25, 71),
        },
        Region {
            centre: (70, 30),
            cols: (40, 98),
            rows: (2, 60),
        },
    ];
    let gate = g(0, 0, 4);
    let mut want = [Lplc2::default(); 3];
    integrate_rows(&m, &nw, &regions, &gate, &mut want);
    for rows in [1, 2, 3, 7] {
        let mut got = [Lplc2::default(); 3];
        integrate_rows(&m, &Narrow { rows, ..nw }, &regions, &gate, &mut got);
        assert_eq!(got, want, "rows {rows}");
    }
}

/// Maps from a seed: noise, noise thinned to sparse dots, or smooth low values.
fn maps_of(seed: u32, kind: u8) -> [[u8; PIXELS]; 4] {
    let mut maps = crate::model::hrc::random_maps(seed);
    for (k, m) in maps.iter_mut().enumerate() {
        for (i, v) in m.iter_mut().enumerate() {
            match kind {
                0 => {}
                1 => {
                    if !(i * 7 + k * 13 + seed as usize).is_multiple_of(5) {
                        *v = 0;
                    }
                }
                _ => *v /= 16,
            }
        }
    }
    maps
}

fn region() -> impl Strategy<Value = Region> {
    (
        0..WIDTH,
        0..HEIGHT,
        1u8..=99,
        any::<bool>(),
        0..WIDTH,
        0..WIDTH,
        0..HEIGHT,
        0..HEIGHT,
    )
        .prop_map(|(x, y, r, square, xa, xb, ya, yb)| {
            if square {
                // a field's clipped square, as the network builds it
                let r = usize::from(r);
                Region {
                    centre: (x, y),
                    cols: (x.saturating_sub(r), (x + r).min(WIDTH - 1)),
                    rows: (y.saturating_sub(r), (y + r).min(HEIGHT - 1)),
                }
            } else {
                // any box on the retina, the centre anywhere (even outside it)
                Region {
                    centre: (x, y),
                    cols: (xa.min(xb), xa.max(xb)),
                    rows: (ya.min(yb), ya.max(yb)),
                }
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]
    #[test]
    fn the_fast_pass_equals_per_field_integration(
        seed in any::<u32>(),
        kind in 0u8..3,
        n in 1u8..=4,
        s in 1u8..=2,
        gain in 1u8..=16,
        w in prop::sample::select(&[0.0f32, 0.25, 0.5, 1.0, 0.3, 2.0, 4.0][..]),
        lm_shift in 0u8..=24,
        floor in 0u32..2000,
        balance in 0u8..=100,
        arms in 0u8..=4,
        regions in prop::collection::vec(region(), 0..=crate::model::MAX_AFS),
    ) {
        let maps = maps_of(seed, kind);
        let cells = cells_of([&maps[0], &maps[1], &maps[2], &maps[3]]);
        let m = Maps::new(&cells);
        let s = if u32::from(n) * u32::from(s) > 8 { 1 } else { s };
        let p = Params { table1: TableOne { n, w, ..Params::PAPER.table1 }, choices: Choices { s, gain, lm_shift, ..Params::PAPER.choices }, ..Params::PAPER };
        prop_assert_eq!(p.validate(), Ok(()));
        let sc = LmScale::new(&p);
        let mut all = [Lplc2::default(); crate::model::MAX_AFS];
        let g = Gate { floor, balance, arms };
        integrate_all(&m, &sc, &regions, &g, &mut all);
        for (r, got) in regions.iter().zip(all.iter()) {
            let want = integrate(&m, &sc, r.centre, r.cols, r.rows, &g);
            prop_assert_eq!(*got, want, "{:?} n{} s{} gain{} w{} shift{}", r, n, s, gain, w, lm_shift);
        }
    }
}

#[test]
fn a_partial_opening_stands_only_on_a_growing_drive() {
    let g = Gate {
        floor: 250,
        balance: 15,
        arms: 3,
    };
    // three arms excited, the fourth silent: the gate opens on 3 of 4
    let three = [1000, 1000, 1000, 0];
    assert_eq!(gate(three, &g), 3000);
    // off: always stands
    assert!(partial_opening_grows(three, &g, Some(10_000), 0));
    // the drive grew from 1,900 to 3,000 (+58 %): stands; from 2,000 (+50 %): not more than half
    assert!(partial_opening_grows(three, &g, Some(1_900), 50));
    assert!(!partial_opening_grows(three, &g, Some(2_000), 50));
    // a steady or falling drive (a receding object, a finished threat's residue): refused
    assert!(!partial_opening_grows(three, &g, Some(3_000), 50));
    assert!(!partial_opening_grows(three, &g, Some(9_000), 50));
    // four excited arms are Eq. (9)'s full opening: no growth needed
    assert!(partial_opening_grows([1000; 4], &g, Some(9_000), 50));
    // a field that jumped has no drive of its new place: a partial opening does not stand,
    // a full one does, and with the option off everything stands
    assert!(!partial_opening_grows(three, &g, None, 50));
    assert!(partial_opening_grows([1000; 4], &g, None, 50));
    assert!(partial_opening_grows(three, &g, None, 0));
}

#[test]
fn a_cut_field_counts_at_its_whole_width() {
    // in the middle the square (73 columns) is whole
    assert_eq!(uncut_response(1_000, 49, 36), 1_000);
    // at column 8 the retina shows columns 0..=44 of it: 45 of 73
    assert_eq!(uncut_response(4_500, 8, 36), 7_300);
    // at column 90, columns 54..=98
    assert_eq!(uncut_response(4_500, 90, 36), 7_300);
    // at the very edge 37 of 73
    assert_eq!(uncut_response(3_700, 0, 36), 7_300);
    assert_eq!(uncut_response(3_700, WIDTH - 1, 36), 7_300);
    // nothing stays nothing, and a huge response saturates
    assert_eq!(uncut_response(0, 0, 36), 0);
    assert_eq!(uncut_response(u32::MAX, 0, 36), u32::MAX);
    // whole from column 36 to 62, cut by one column outside them
    assert_eq!(uncut_response(7_200, 36, 36), 7_200);
    assert_eq!(uncut_response(7_200, 35, 36), 7_300);
    assert_eq!(uncut_response(7_200, 62, 36), 7_200);
    assert_eq!(uncut_response(7_200, 63, 36), 7_300);
    // a field wider than the retina is scaled by what it shows; a one-column field is whole
    assert_eq!(uncut_response(99, 49, 99), 199);
    assert_eq!(uncut_response(5, 3, 0), 5);
    // a centre off the retina (no field has one) does not panic
    assert_eq!(uncut_response(5, usize::MAX, 36), 365);
}
