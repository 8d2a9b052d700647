//! The cycle model's prediction of the boot self-test for the same release build (what
//! `cargo alvs budget --boot --json` prints), to hold a board's `bench:` lines against.

use alvs_tasks::robot::self_test::STAGE_NAMES;
use anyhow::{ensure, Context, Result};
use serde::{Deserialize, Serialize};

/// One self-test frame under the model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PredictedFrame {
    /// Self-test frame, 0 first.
    pub frame: u32,
    /// Attention fields standing after it.
    pub afs: u32,
    /// Nominal cycles per stage ([`STAGE_NAMES`] order).
    pub nominal: Vec<u64>,
    /// Pessimistic cycles per stage.
    pub pessimistic: Vec<u64>,
}

/// The worst frame the budget documents (docs/budget.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WorstCase {
    pub scene: String,
    pub frame: u32,
    pub pessimistic: u64,
    pub nominal: u64,
    /// Where the figure comes from.
    pub source: String,
}

/// The model's self-test and worst case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    pub stages: Vec<String>,
    pub frames: Vec<PredictedFrame>,
    pub worst_case: Option<WorstCase>,
}

impl Prediction {
    /// Reads `alvs-budget --boot --json`'s output; other stages than the firmware's are an
    /// error.
    pub fn from_json(text: &str) -> Result<Prediction> {
        let p: Prediction =
            serde_json::from_str(text.trim()).context("the cycle model's self-test output")?;
        ensure!(
            p.stages == STAGE_NAMES
                && p.frames.iter().all(|f| {
                    f.nominal.len() == STAGE_NAMES.len() && f.pessimistic.len() == STAGE_NAMES.len()
                }),
            "the cycle model reports other stages than {STAGE_NAMES:?}"
        );
        Ok(p)
    }

    /// Self-test frame `frame`'s prediction.
    pub fn frame(&self, frame: u32) -> Option<&PredictedFrame> {
        self.frames.iter().find(|f| f.frame == frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_budget_tools_json() {
        let json = r#"{"stages":["retina","attention","motion","visuomotor","control"],"frames":[{"frame":0,"afs":0,"nominal":[20747,0,0,0,3342],"pessimistic":[22931,0,0,0,3988]}],"worst_case":{"scene":"test_black_approach","frame":49,"pessimistic":1784382,"nominal":1681455,"source":"docs/budget.md"}}"#;
        let p = Prediction::from_json(json).unwrap();
        assert_eq!(p.frame(0).map(|f| f.pessimistic[0]), Some(22931));
        assert_eq!(p.worst_case.map(|w| w.pessimistic), Some(1_784_382));
        let other = json.replace("\"control\"", "\"fsm\"");
        assert!(Prediction::from_json(&other).is_err());
        assert!(Prediction::from_json("cargo: error").is_err());
    }
}
