//! The visuomotor pathway (paper Sec. II-B): premotor convergence of every attention field's
//! LPLC2 response into an escape strength, a threat direction and the escape headings.
//!
//! Angle convention (paper): the robot's forward direction is 0°, left turns are negative,
//! right turns positive, every angle wrapped to (−180°, 180°]. A threat on the right of the
//! image (`X̄ > 49`) is at a positive bearing.

use crate::frame::CENTRE_X;
use crate::model::closed_loop::movers::Sighting;
use crate::model::closed_loop::progress::View;
use crate::model::params::Params;

/// What the premotor neurons make of one frame's LPLC2 responses.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Visuomotor {
    /// `ΣLPLC2_k(t)` over the existing attention fields (saturating).
    pub lplc2_sum: u32,
    /// `S(t)`, Eq. (11): escape strength in [0.5, 1).
    pub strength: f32,
    /// `X̄(t)`, Eq. (12): LPLC2-weighted horizontal centroid of the threat, in pixels 0..=98;
    /// `None` when no field responds.
    pub threat_x: Option<f32>,
    /// This frame triggers an escape: some attention field is stimulated (LPLC2_k > 0).
    pub alert: bool,
    /// The global threat exceeds `T_s`: the short-mode escape overrides every state.
    pub short_mode: bool,
    /// `θ_long(t)`, Eq. (13), relative to the current heading, wrapped; `None` without threat.
    pub theta_long: Option<f32>,
    /// `[θ¹_short, θ²_short]`, Eqs. (14)–(15), relative to the heading; `None` without threat.
    pub theta_short: Option<[f32; 2]>,
    /// The frame's coarse view for the blocked-way test, with its threshold
    /// (`Params::blocked_change`); `None` when that mechanism is off (the paper's model).
    pub view: Option<(View, u8)>,
    /// The floor line (`Params::floor_row`) found an obstacle close ahead in the robot's path
    /// on this frame: the heading 90° away from its side (`θ¹_short` of its column, relative,
    /// whatever the fields report). Unlike a field's alert a distance, so the FSM acts on it
    /// at once. `None` without one.
    pub obstacle: Option<f32>,
    /// What the swarm's look found on this frame (`Params::look_change`,
    /// [`crate::model::closed_loop::movers::Movers`], run beside the network; the network leaves it `None`):
    /// `Some` once per look of a robot commanded to stand, `None` on every other frame.
    pub sighting: Option<Sighting>,
}

impl Visuomotor {
    /// An obstacle close ahead in column `x` (`Params::floor_row`). On a frame no field
    /// alerts on, also an alert whose threat is there, at the lowest strength and without the
    /// short mode (ΣLPLC2 stays 0); otherwise the fields' threat stands.
    #[inline(always)]
    pub fn ahead(&mut self, x: u8, p: &Params) {
        let x = f32::from(x);
        let short = theta_short(x, p.table1.alpha);
        self.obstacle = Some(short[0]);
        if self.alert {
            return;
        }
        self.alert = true;
        self.threat_x = Some(x);
        self.theta_long = Some(theta_long(x, p.table1.alpha));
        self.theta_short = Some(short);
    }

    /// Converges the fields' `(x̄_k, LPLC2_k)` pairs into the visuomotor signals.
    pub fn from_fields(fields: impl Iterator<Item = (u8, u32)> + Clone, p: &Params) -> Self {
        let sum = fields
            .clone()
            .fold(0u32, |acc, (_, r)| acc.saturating_add(r));
        // Eq. (12) in f32: once per frame, over at most MAX_AFS terms. The denominator is summed
        // in f32 like the numerator, not taken from the saturating integer sum, so X̄ stays a
        // weighted mean of the fields' columns even when responses saturate.
        let threat_x = (sum > 0).then(|| {
            let (num, den) = fields.fold((0.0f32, 0.0f32), |(n, d), (x, r)| {
                (n + f32::from(x) * r as f32, d + r as f32)
            });
            num / den
        });
        let alert = sum > 0;
        Visuomotor {
            lplc2_sum: sum,
            strength: strength(sum, p.table1.w_s),
            threat_x,
            alert,
            short_mode: sum > p.table1.t_s,
            theta_long: threat_x.map(|x| theta_long(x, p.table1.alpha)),
            theta_short: threat_x.map(|x| theta_short(x, p.table1.alpha)),
            view: None,
            obstacle: None,
            sighting: None,
        }
    }
}

/// Eq. (11): `S = 1 / (1 + exp(−ΣLPLC2 / w_s))`.
pub fn strength(lplc2_sum: u32, w_s: f32) -> f32 {
    1.0 / (1.0 + libm::expf(-(lplc2_sum as f32) / w_s))
}

/// Bearing of an image column in degrees (`α (x − 49)`), positive to the right.
pub fn bearing(x: f32, alpha: f32) -> f32 {
    alpha * (x - CENTRE_X)
}

/// Eq. (13): `θ_long = α (X̄ − 49) + 180°`, wrapped: turn to face away from the threat.
pub fn theta_long(threat_x: f32, alpha: f32) -> f32 {
    wrap_deg(bearing(threat_x, alpha) + 180.0)
}

/// Eqs. (14)–(15): the two headings of the short-mode γ path, relative to the heading at the
/// trigger. Phase 1 ends 90° off the threat, phase 2 faces 180° away from it.
pub fn theta_short(threat_x: f32, alpha: f32) -> [f32; 2] {
    let b = bearing(threat_x, alpha);
    let t1 = if threat_x - CENTRE_X >= 0.0 {
        b - 90.0
    } else {
        b + 90.0
    };
    let t2 = if t1 < 0.0 { t1 - 90.0 } else { t1 + 90.0 };
    [wrap_deg(t1), wrap_deg(t2)]
}

/// Wraps an angle in degrees to (−180°, 180°]; non-finite input gives 0.
pub fn wrap_deg(a: f32) -> f32 {
    if !a.is_finite() {
        return 0.0;
    }
    let mut r = libm::fmodf(a, 360.0);
    if r > 180.0 {
        r -= 360.0;
    } else if r <= -180.0 {
        r += 360.0;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-3
    }

    #[test]
    fn strength_is_the_sigmoid_of_eq_11() {
        assert!(close(strength(0, 4000.0), 0.5));
        // 1 / (1 + e^-1)
        assert!(close(strength(4000, 4000.0), 0.731_058_6));
        assert!(close(strength(8000, 4000.0), 0.880_797));
    }

    #[test]
    fn theta_long_faces_away_from_the_threat() {
        // threat dead ahead: turn around
        assert!(close(theta_long(49.0, 0.707), 180.0));
        // threat at the right edge (+34.6°): face 180° away, i.e. −145.4°
        assert!(close(theta_long(98.0, 0.707), -145.357));
        // threat at the left edge: +145.4°
        assert!(close(theta_long(0.0, 0.707), 145.357));
    }

    #[test]
    fn theta_short_is_the_gamma_path() {
        // right threat at +34.643°: phase 1 to −55.357° (threat 90° on the right), phase 2 to −145.357°
        let [t1, t2] = theta_short(98.0, 0.707);
        assert!(close(t1, -55.357) && close(t2, -145.357), "{t1} {t2}");
        // left threat at −34.643°: +55.357°, then +145.357°
        let [t1, t2] = theta_short(0.0, 0.707);
        assert!(close(t1, 55.357) && close(t2, 145.357), "{t1} {t2}");
        // dead ahead counts as right (X̄ − 49 ≥ 0): −90° then −180° = 180° wrapped
        let [t1, t2] = theta_short(49.0, 0.707);
        assert!(close(t1, -90.0) && close(t2, 180.0), "{t1} {t2}");
    }

    #[test]
    fn wrap_is_half_open() {
        assert!(close(wrap_deg(180.0), 180.0));
        assert!(close(wrap_deg(-180.0), 180.0));
        assert!(close(wrap_deg(190.0), -170.0));
        assert!(close(wrap_deg(-190.0), 170.0));
        assert!(close(wrap_deg(725.0), 5.0));
        assert_eq!(wrap_deg(f32::NAN), 0.0);
    }

    #[test]
    fn centroid_weights_fields_by_response() {
        let p = Params::default();
        let fields = [(20u8, 1000u32), (80u8, 3000u32), (50u8, 0u32)];
        let v = Visuomotor::from_fields(fields.iter().copied(), &p);
        assert_eq!(v.lplc2_sum, 4000);
        assert!(close(v.threat_x.unwrap(), 65.0));
        assert!(v.alert && !v.short_mode);
        let none = Visuomotor::from_fields([(10u8, 0u32)].iter().copied(), &p);
        assert_eq!(
            (none.alert, none.threat_x, none.theta_long),
            (false, None, None)
        );
        let big = Visuomotor::from_fields([(10u8, 7001u32)].iter().copied(), &p);
        assert!(big.short_mode);
    }
}
