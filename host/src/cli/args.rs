//! The command line: `alvs` and its subcommands. Each variant's doc comment is its `--help`
//! text; the options of each are in the module that runs it.

use std::path::PathBuf;

use clap::{Parser, Subcommand};

use super::log::LogArgs;
use super::multi::MultiArgs;
use super::paper::{ArenaArgs, EvasionArgs, StimuliArgs, SwarmArgs, TwoThreatArgs};
use super::recordings::RecordingsCmd;
use super::replay::{ModelArgs, ReplayArgs};
use super::shards::MergeArgs;
use super::suites::{AblationArgs, RobustnessArgs};
use super::tables::TablesArgs;
use super::validate::ValidateArgs;

#[derive(Parser)]
#[command(
    name = "alvs",
    version,
    about = "Host tools for the ALVS firmware: the exact task code on recorded or synthetic video"
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
}

#[derive(Subcommand)]
pub enum Cmd {
    /// Run the perception and motor-control tasks on a clip; one JSON object per frame on stdout.
    Replay(ReplayArgs),
    /// Run the built-in synthetic scenes (approach left/centre/right, recede, translate, double
    /// and triple approach) and write their pictures.
    Demo {
        /// Where the pictures go.
        #[arg(long, default_value = "out/demo")]
        png: PathBuf,
        #[command(flatten)]
        model: ModelArgs,
    },
    /// Experiment 4 (paper Figs. 5-6): robots wander in the walled arena; success rate,
    /// collisions per minute, time per state and trajectory pictures per controller and
    /// background.
    ///
    /// One trial is one controller on one background: all robots run that controller for
    /// --minutes of simulated time. A collision is a centre distance below one robot diameter
    /// (42 mm) between two robots or between a robot and the wall; an encounter is two bodies
    /// within two diameters of each other (surface to surface); success rate = encounters
    /// without a collision / encounters. Every controller starts from the same poses with the
    /// same seed (a paired comparison). Trials run in parallel; results depend only on the
    /// options, never on --jobs.
    ///
    /// With no option: 3 robots, 10 minutes, backgrounds clutter:1, stripes:40 and checker:60,
    /// controllers alvs and lgmd2, seed 1; a table on stdout, pictures in out/arena.
    Arena(ArenaArgs),
    /// The firmware's frame budget on the Cortex-M4 cycle model: cycles per stage, RAM.
    ///
    /// Builds the firmware, times its perception + control step on worst cases and clips,
    /// prints the table; `--json` for tooling. Runs `alvs-budget` of the crate alvs-cycles,
    /// which needs cmake and libclang-dev (./test.sh installs them); `cargo alvs budget --help`
    /// lists its options.
    #[command(disable_help_flag = true)]
    Budget {
        /// Options of alvs-budget (e.g. --json, --all-clips, --write-doc docs/budget.md).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// The unmodified firmware ELF on a virtual Colias board: RTT tabs and a timing report.
    ///
    /// Boots the release firmware from its reset vector on the Cortex-M4 model with a host
    /// NVIC and models of the camera (OV7670 over SCCB, DCMI, DMA), UART4, watchdog and RTT;
    /// prints the log and telemetry tabs as `cargo embed` shows them, then frame complete →
    /// first motor byte latency, CPU load per interrupt, dropped frames. Runs `alvs-virtual`
    /// of the crate alvs-cycles (cmake and libclang-dev, as for `budget`); `cargo alvs virtual
    /// --help` lists its options (--clip, --seconds, --blanking, --sweep-blanking, ...).
    #[command(disable_help_flag = true)]
    Virtual {
        /// Options of alvs-virtual (e.g. --clip data/clips/real_bird_attack.y8 --seconds 3).
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// Experiment 1 (paper Fig. 3): a standing ALVS robot watches obstacle robots translate,
    /// recede, approach, and two and three approach at once; attention-field tracks, LPLC2
    /// traces and layer pictures per scene.
    Stimuli(StimuliArgs),
    /// Paper Fig. 3 (e)-(f) on recorded video: attention fields over time on the authors' two
    /// multi-target clips (dark squares expanding at known places and times over a scrolling
    /// photograph), the paper's model beside the default and beside the fields the authors'
    /// own offline model kept on the same clips; does each object get a field of its own?
    MultiTarget(MultiArgs),
    /// Experiment 2 (paper Fig. 4a,c,d): one obstacle robot approaches the standing tested
    /// robot at a constant speed from 9 bearings, -35..35 deg; per bearing, did it escape to
    /// the side away from the obstacle, and did it collide? ALVS and LGMD2 with the same seed.
    Evasion(EvasionArgs),
    /// Experiment 3 (paper Fig. 4b): two obstacle robots approach at once from opposite sides
    /// at unequal speeds; over --runs random geometries, how often does the tested robot end
    /// on the side away from the faster one?
    TwoThreats(TwoThreatArgs),
    /// Experiment 5 (paper Fig. 7): robots in the spin-on-approach (swarm) mode wander in the
    /// arena; the spread of the group over time, against the same robots escaping.
    Swarm(SwarmArgs),
    /// The simulator against the real recordings: one LGMD2 robot per recorded run, alone in
    /// the recorded arena's replica at the run's speed; its path's statistics beside the real
    /// one's, each with its tolerance (the 10.9 cm/s runs calibrate, the rest are held out).
    ///
    /// The simulated trail is drawn and extracted exactly as the tracker's snapshots are
    /// (`cargo alvs recordings`). Pictures: real and simulated path side by side per run.
    Validate(ValidateArgs),
    /// The robustness suite (issue 29): every controller (alvs, paper, lgmd2) in the validated
    /// world under each perturbation a real lab or robot brings (textured and shaded floor,
    /// camera height +-5 mm and pitch +-2 deg, a lighting gradient, a 5 % weaker motor, the
    /// firmware's odometry heading, lost frames), over seeds 11-20 by default.
    ///
    /// One trial is the arena experiment's (its robots, counting and noise) with one
    /// perturbation, one controller and one seed. One row per (perturbation, controller): the
    /// success rate with its encounters (seeds pooled) and one seed's lowest-highest, the mean
    /// speed and its share of the cruise speed (SLOW below 80 %), the time pressed against a
    /// wall or obstacle, and the change from the unperturbed row. docs/robustness.md gives
    /// each perturbation's magnitude and its source.
    Robustness(RobustnessArgs),
    /// The ablation (issue 30): every mechanism of the default removed one at a time, and
    /// added to the paper's model one at a time, beside the default, the paper's model and
    /// LGMD2, on the same seeds (11-20 by default) in the validated world: the arena (success
    /// with its encounters, mean speed, time at a wall, time escaping), evasion on three walls
    /// (correct side, collisions, seeds at the goal of 9/9 correct with at most one
    /// collision) and two threats (away from the faster, collisions). docs/ablation.md.
    Ablation(AblationArgs),
    /// The headline figures of stimuli, evasion, two-threats, arena and swarm in one world over
    /// several seeds (the report seeds 11-20 by default), printed as the markdown tables of
    /// docs/experiments.md: each row is the experiment's own default run in that world with
    /// that seed (and the arena's paper row with --model paper), so one command regenerates a
    /// table when the world changes. All five in fu2019 take about 25 minutes on one core.
    Tables(TablesArgs),
    /// The real Colias recordings (fuqinbing/LGMD2-open-source, issue 29): extract the arena
    /// and the tracks from the tracker's snapshots, or show the committed statistics.
    Recordings {
        #[command(subcommand)]
        cmd: RecordingsCmd,
    },
    /// Pool the shard files of a sweep (an experiment run as `--shard I/N --json FILE` for
    /// I = 1..N, on one machine or many) into the report an unsharded run gives: the same
    /// table, JSON and pictures (docs/sweeps.md).
    ///
    /// The shards carry their command line, configuration and program version, so nothing
    /// about the run is given again here (nor are its background pictures needed); shards of
    /// different runs or builds, a missing or repeated shard and an unreadable file are
    /// refused. A merged `stimuli` draws its tracks pictures only: the layer pictures replay
    /// camera frames the shard files do not carry.
    Merge(MergeArgs),
    /// Read back a saved RTT session of the firmware (what Embed.toml's `log_enabled` makes
    /// `cargo embed` write, or a tab's text piped in) and summarise it: frames, drops, cycles
    /// per frame against the 33 ms period, time per FSM state, alerts, attention fields, each
    /// boot and what reset it, the boot self-test's `bench:` cycles next to the cycle model's
    /// for this build, and every line that could not be read (docs/log.md).
    Log(LogArgs),
}
