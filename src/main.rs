//! # alvs-firmware: RTIC 2 firmware for the Colias sense board (STM32F427VI)
//!
//! Camera in, escape out, telemetry over RTT. Tasks, highest priority first (docs/firmware.md
//! has the diagram and what each shares):
//!
//! | task | priority | runs on | does |
//! |---|---|---|---|
//! | `uart4` | 5 | UART4 TXE | feeds the motor link one byte at a time |
//! | `dcmi`, `dma_lines` | 4 | DCMI / DMA2 stream 1 interrupts | frame start/complete/overrun; lines stream into the retina |
//! | `motor_control`, `supervisor` | 3 | each perception / every 10 ms | escape FSM → motor frames; safety policy, watchdog |
//! | `perception` | 2 | each delivered frame | the rest of the aLPLC2 step, DWT-timed |
//! | `telemetry`, `summary` | 1 | each record / every second | RTT channel 1 lines, channel 0 summary |
//!
//! Everything that is not a register access lives in `alvs-tasks` and is tested on the host.
//! Flash and watch the log with `cargo embed --release` (see `Embed.toml`).
#![no_std]
#![no_main]

mod bench;
mod board;
mod camera;
mod capture;
mod ccm;
mod fault;
mod motor_link;
mod setup;

// A panic prints its message over RTT (up channel 0 "log"), then `udf` lands in the HardFault
// handler of `fault`, which stops the motors and waits for the watchdog reset.
use panic_probe as _;

/// Records dropped on the way to the host: telemetry queue full, or RTT buffer full because no
/// probe reads it (the robot never waits for the host).
static RTT_DROPPED: core::sync::atomic::AtomicU32 = core::sync::atomic::AtomicU32::new(0);

/// Depth of the queue from motor control to the telemetry task.
const TELEMETRY_QUEUE: usize = 4;

/// The motor-control task's behaviour at boot: the escape FSM. `s` typed on RTT down channel 0
/// switches to the swarm's spin on an approaching robot (paper Sec. IV-D), `e` back, without
/// reflashing.
const BOOT_BEHAVIOUR: alvs_tasks::model::fsm::Behaviour = alvs_tasks::model::fsm::Behaviour::Escape;

// Dispatchers for the software tasks (priorities 1, 2, 3): the interrupts of SPI4, SPI5 and
// SPI6, peripherals this firmware does not use and docs/hardware.md assigns nothing to.
// RTIC's generated `spawn` returns its message in `Err`: a `Perception` (≈ 240 B) for motor
// control, copied once per frame; boxing is not an option without a heap.
#[allow(clippy::result_large_err)]
#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true, dispatchers = [SPI4, SPI5, SPI6])]
mod app {
    use crate::capture::FrameIn;
    use crate::motor_link::MotorLink;
    use crate::{bench, camera, setup, BOOT_BEHAVIOUR, RTT_DROPPED, TELEMETRY_QUEUE};
    use alvs_tasks::model::closed_loop::movers::Movers;
    use alvs_tasks::model::fsm::{Behaviour, FsmParams};
    use alvs_tasks::model::param_table::off0;
    use alvs_tasks::robot::camera::{Counters, FrameEnd};
    use alvs_tasks::robot::control::Control;
    use alvs_tasks::robot::health::{
        console_command, ConsoleCommand, Fault, Safety, SummaryWindow, WATCHDOG_TIMEOUT_MS,
    };
    use alvs_tasks::robot::telemetry::Record;
    use alvs_tasks::{Network, Perception};
    use core::sync::atomic::Ordering;
    use cortex_m::peripheral::DWT;
    // The HAL's prelude (its fugit) for clocks and the watchdog; of the monotonic's prelude
    // only the macro and the trait, with its own duration type (another fugit version).
    use rtic_monotonics::systick::prelude::{systick_monotonic, Monotonic};
    use rtic_sync::channel::{Receiver, Sender};
    use rtic_sync::make_channel;
    use rtt_target::{rprintln, rtt_init, set_print_channel, DownChannel, UpChannel};
    use stm32f4xx_hal::prelude::*;
    use stm32f4xx_hal::watchdog::IndependentWatchdog;

    systick_monotonic!(Mono, 1_000);
    type MonoDuration = <Mono as Monotonic>::Duration;

    /// Milliseconds since boot (wraps after 49 days; every user subtracts with wrapping).
    fn now_ms() -> u32 {
        Mono::now().ticks()
    }

    #[shared]
    struct Shared {
        /// Camera side: DCMI, capture policy, the network while rows stream in.
        #[lock_free]
        frames: FrameIn,
        /// The network when perception has finished with it, waiting for the next VSYNC.
        parked: Option<&'static mut Network>,
        safety: Safety,
        /// Capture totals, copied at each frame end for the summary.
        counters: Counters,
        /// Per-second cycle statistics.
        stats: SummaryWindow,
        control: Control,
        link: MotorLink,
        /// The supervisor asks the camera side to start the model afresh (after a fault).
        reset_requested: bool,
    }

    #[local]
    struct Local {
        telemetry: UpChannel,
        /// RTT down channel 0 "control": `h` holds the motors, `g` lets them go.
        console: DownChannel,
        records_tx: Sender<'static, Record, TELEMETRY_QUEUE>,
        records_rx: Receiver<'static, Record, TELEMETRY_QUEUE>,
        watchdog: IndependentWatchdog,
        /// The camera's XCLK and SCCB, kept alive (and for a future re-initialisation).
        camera: camera::Camera,
        last_fault: Option<Fault>,
    }

    #[init]
    fn init(cx: init::Context) -> (Shared, Local) {
        // RTT first (it needs no clock set-up), so that a panic or a hang in the clock
        // configuration below is visible on the probe. Channel 0 "log" (text, the print channel
        // of `rprintln!` and of panic-probe's `print-rtt`), channel 1 "telemetry". Both
        // NoBlockSkip: output is dropped, never blocking, when no probe reads it (the robot runs
        // untethered). Down channel 0 "control" takes one-letter commands (`h` hold, `g` go).
        let channels = rtt_init! {
            up: {
                0: {
                    size: 1024,
                    name: "log"
                }
                1: {
                    // ~3 KB/s of lines; a probe polls many times a second
                    size: 1024,
                    name: "telemetry"
                }
            }
            down: {
                0: {
                    // one letter at a time: a hold is typed, not streamed
                    size: 4,
                    name: "control"
                }
            }
        };
        set_print_channel(channels.up.0);
        rprintln!(
            "alvs-firmware {} on the Colias sense board (STM32F427VI)",
            env!("CARGO_PKG_VERSION")
        );
        let mut core = cx.core;
        let dp = cx.device;
        let mut rcc = setup::clocks(dp.RCC, &dp.DBGMCU);

        // DWT cycle counter: the perception timing and the self-benchmark read it.
        core.DCB.enable_trace();
        core.DWT.enable_cycle_counter();
        // SAFETY: init runs once, and nothing has touched CCM's data before this line.
        let network: &'static mut Network = unsafe { crate::ccm::take_network() };
        bench::self_test(network);

        let ports = setup::Ports {
            a: dp.GPIOA.split(&mut rcc),
            b: dp.GPIOB.split(&mut rcc),
            c: dp.GPIOC.split(&mut rcc),
            e: dp.GPIOE.split(&mut rcc),
        };
        let (camera, dcmi, camera_ok, motor_tx) = setup::camera(ports, &mut rcc, dp.DCMI, dp.DMA2);
        // Motors disabled at boot: the stop frames go out first.
        let mut link = setup::motor_link(dp.UART4, motor_tx, &mut rcc);
        let mut control = Control::new(FsmParams::default(), BOOT_BEHAVIOUR);
        link.send(&control.stop());

        let (records_tx, records_rx) = make_channel!(Record, TELEMETRY_QUEUE);
        Mono::start(core.SYST, rcc.clocks.sysclk().raw());
        let mut watchdog = IndependentWatchdog::new(dp.IWDG);
        watchdog.start(WATCHDOG_TIMEOUT_MS.millis());
        // Without a camera nothing is captured: the network stays unused, the watchdog starves
        // and resets the MCU, which tries the camera again.
        let mut frames = FrameIn::new(dcmi);
        let parked = camera_ok.then(|| {
            frames.capture_start();
            network
        });
        rprintln!(
            "running: model alvs = Table I (T_a {}, T_d {}, T_s {}) + warm-up {} frames, flicker {} %, noise frames below {} % neighbour correlation, derotate {}, gate {} of 4 arms (growing {} %, or on {} frames in a row), T_a {} in a quiet scene, blind border arms {} (a side cut once the field crosses it {}) and cut fields whole for T_s {} and the short mode on an alert in a field's first d frames {} while standing, fields above row {} silent and the floor line at row {} while driving, escape saccade {}, jump {} frames from standing, brisk gamma path {}, {} B of model state, motors off until {} frames primed it; type h to hold them, g to let go; behaviour {} (type s for the swarm's spin, e to escape)",
            alvs_tasks::Params::ALVS.table1.t_a,
            alvs_tasks::Params::ALVS.table1.t_d,
            alvs_tasks::Params::ALVS.table1.t_s,
            off0(alvs_tasks::Params::ALVS.mechanisms.warmup),
            off0(alvs_tasks::Params::ALVS.mechanisms.flicker_pct),
            off0(alvs_tasks::Params::ALVS.mechanisms.noise_pct),
            u8::from(alvs_tasks::Params::ALVS.efference.derotate),
            alvs_tasks::Params::ALVS.choices.q_arms,
            off0(alvs_tasks::Params::ALVS.mechanisms.q_grow_pct),
            off0(alvs_tasks::Params::ALVS.mechanisms.q_grow_run),
            off0(alvs_tasks::Params::ALVS.mechanisms.t_a_quiet),
            u8::from(alvs_tasks::Params::ALVS.mechanisms.border_arms),
            u8::from(alvs_tasks::Params::ALVS.mechanisms.border_crossing),
            u8::from(alvs_tasks::Params::ALVS.short.short_uncut),
            u8::from(alvs_tasks::Params::ALVS.short.short_young),
            off0(alvs_tasks::Params::ALVS.efference.band_row),
            off0(alvs_tasks::Params::ALVS.efference.floor_row),
            u8::from(FsmParams::ALVS.escape.escape_saccade),
            off0(FsmParams::ALVS.escape.jump_frames),
            u8::from(FsmParams::ALVS.escape.gamma_turn),
            core::mem::size_of::<Network>(),
            alvs_tasks::robot::health::PRIME_FRAMES,
            BOOT_BEHAVIOUR.name()
        );
        supervisor::spawn().ok();
        summary::spawn().ok();
        telemetry::spawn().ok();

        (
            Shared {
                frames,
                parked,
                safety: Safety::new(),
                counters: Counters::ZERO,
                stats: SummaryWindow::new(),
                control,
                link,
                reset_requested: false,
            },
            Local {
                telemetry: channels.up.1,
                console: channels.down.0,
                records_tx,
                records_rx,
                watchdog,
                camera,
                last_fault: None,
            },
        )
    }

    /// Sleeps between interrupts. `wfi` should not disturb the probe since `init` set
    /// DBG_SLEEP; should the probe still lose the target, replace it with `nop`.
    #[idle(local = [camera])]
    fn idle(_cx: idle::Context) -> ! {
        loop {
            cortex_m::asm::wfi();
        }
    }

    /// DMA half/complete: two more lines are in the ring; they stream into the retina (or the
    /// backlog, while perception still owns the network: taken back here once it is parked).
    #[task(binds = DMA2_STREAM1, priority = 4, shared = [frames, parked])]
    fn dma_lines(cx: dma_lines::Context) {
        let frames = cx.shared.frames;
        let mut parked = cx.shared.parked;
        parked.lock(|p| frames.offer(p));
        frames.drain();
    }

    /// DCMI: overrun, sync error, frame complete (→ perception), VSYNC (→ next frame).
    #[task(binds = DCMI, priority = 4, shared = [frames, parked, safety, counters, reset_requested])]
    fn dcmi(cx: dcmi::Context) {
        let frames = cx.shared.frames;
        let mut safety = cx.shared.safety;
        let e = frames.dcmi.take_events();
        if e.overrun {
            frames.capture.overrun();
            let now = now_ms();
            safety.lock(|s| s.overrun(now));
        }
        if e.sync_error {
            frames.capture.sync_error();
        }
        let mut parked = cx.shared.parked;
        if e.frame {
            parked.lock(|p| frames.offer(p));
            let (end, network) = frames.frame_complete();
            if let (FrameEnd::Deliver { .. }, Some(network)) = (end, network) {
                if let Err((network, _)) = perception::spawn(network, frames.retina_cycles) {
                    // cannot happen (perception gave the network back before this frame
                    // began); keep it for the next frame
                    frames.network = Some(network);
                }
            }
            let totals = frames.capture.counters();
            let mut counters = cx.shared.counters;
            counters.lock(|c| *c = totals);
        }
        if e.vsync {
            let start = frames.frame_start(parked.lock(|p| p.take()));
            let mut reset = cx.shared.reset_requested;
            if start.accepted && reset.lock(core::mem::take) {
                if let Some(n) = frames.network.as_deref_mut() {
                    n.reset();
                }
            }
        }
    }

    /// The rest of the aLPLC2 step on the frame whose rows are in; motor control gets the
    /// result and the network, which it parks once the network has taken the turn.
    #[task(priority = 2, shared = [parked, safety, stats])]
    async fn perception(
        mut cx: perception::Context,
        network: &'static mut Network,
        retina_cycles: u32,
    ) {
        let t0 = DWT::cycle_count();
        let result = network.end_frame();
        let cycles = retina_cycles.wrapping_add(DWT::cycle_count().wrapping_sub(t0));
        match result {
            Ok(p) => {
                let now = now_ms();
                cx.shared.safety.lock(|s| s.frame(now));
                cx.shared.stats.lock(|w| w.record_frame(cycles));
                if let Err((network, ..)) = motor_control::spawn(network, p, cycles) {
                    cx.shared.parked.lock(|p| *p = Some(network));
                    rprintln!("ERROR perception: motor control still busy");
                }
            }
            // the capture policy delivers only whole frames
            Err(e) => {
                cx.shared.parked.lock(|p| *p = Some(network));
                rprintln!("ERROR perception: {}", e);
            }
        }
    }

    /// The escape FSM on this frame's perception; wheel powers to the bottom board; the turn
    /// and forward speed they make until the next frame to the network (its efference copies,
    /// `Network::turned`, `Network::driving`),
    /// which is then parked for the camera; the frame's telemetry record to the telemetry task.
    /// Rows arriving meanwhile wait in the camera side's backlog.
    #[task(priority = 3, shared = [safety, control, link, parked], local = [records_tx, movers: Movers = Movers::new()])]
    async fn motor_control(
        mut cx: motor_control::Context,
        network: &'static mut Network,
        p: Perception,
        cycles: u32,
    ) {
        let enable = cx.shared.safety.lock(|s| s.motors_allowed());
        let movers = cx.local.movers;
        let (command, frames, turn, forward) = cx.shared.control.lock(|c| {
            let look = Some((
                &mut *movers,
                network.frame(),
                off0(network.params().swarm.look_change),
            ));
            let (command, frames) = c.step_seeing(&p.vm, look, enable);
            (command, frames, c.last_turn_deg(), c.last_forward_mm_s())
        });
        cx.shared.link.lock(|l| l.send(&frames));
        network.turned(turn);
        network.driving(forward);
        cx.shared.parked.lock(|p| *p = Some(network));
        let record = Record::from_perception(&p, command.state, cycles);
        if cx.local.records_tx.try_send(record).is_err() {
            RTT_DROPPED.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// Every 10 ms: the safety policy. Feeds the watchdog on perception progress, stops the
    /// motors on a fault (camera stall, overrun burst) or a hold typed on RTT, and asks for a
    /// fresh model after a fault.
    #[task(priority = 3, shared = [safety, control, link, reset_requested], local = [watchdog, last_fault, console])]
    async fn supervisor(mut cx: supervisor::Context) {
        loop {
            match typed_command(cx.local.console) {
                Some(ConsoleCommand::Mode(b)) => {
                    cx.shared.control.lock(|c| c.set_behaviour(b));
                    rprintln!("{}", behaviour_line(b));
                }
                Some(hold) => {
                    let on = hold == ConsoleCommand::Hold;
                    if cx.shared.safety.lock(|s| s.hold(on)) {
                        rprintln!(
                            "{}",
                            if on {
                                "held: motors off ('g' lets go)"
                            } else {
                                "let go"
                            }
                        );
                    }
                }
                None => {}
            }
            let now = now_ms();
            let d = cx.shared.safety.lock(|s| s.tick(now));
            if d.feed_watchdog {
                cx.local.watchdog.feed();
            }
            if d.fault != *cx.local.last_fault {
                match d.fault {
                    Some(f) => {
                        rprintln!("ERROR {}: motors stopped; the model primes again", f.name());
                        cx.shared.reset_requested.lock(|r| *r = true);
                    }
                    None => rprintln!("recovered: frames flow again"),
                }
                *cx.local.last_fault = d.fault;
            }
            if !d.motors_enabled {
                let stop = cx
                    .shared
                    .control
                    .lock(|c| c.motors_enabled().then(|| c.stop()));
                if let Some(stop) = stop {
                    cx.shared.link.lock(|l| l.send(&stop));
                }
            }
            Mono::delay(MonoDuration::millis(10)).await;
        }
    }

    /// The command typed on the RTT control channel since the last look, if any (a function,
    /// so that its buffer is not kept across the supervisor's await).
    fn typed_command(console: &mut DownChannel) -> Option<ConsoleCommand> {
        let mut typed = [0u8; 4];
        let n = console.read(&mut typed);
        console_command(typed.get(..n).unwrap_or(&[]))
    }

    /// The log line that names a behaviour and how to switch.
    fn behaviour_line(b: Behaviour) -> &'static str {
        match b {
            Behaviour::Escape => "behaviour: escape (s for the swarm's spin)",
            Behaviour::Swarm => "behaviour: swarm, spin on an approaching robot (e to escape)",
        }
    }

    /// UART4 TXE: the next queued byte to the bottom board.
    #[task(binds = UART4, priority = 5, shared = [link])]
    fn uart4(mut cx: uart4::Context) {
        cx.shared.link.lock(|l| l.on_interrupt());
    }

    /// RTT channel 1: one line per frame; dropped (and counted) when the host does not read.
    #[task(priority = 1, local = [telemetry, records_rx])]
    async fn telemetry(cx: telemetry::Context) {
        while let Ok(record) = cx.local.records_rx.recv().await {
            // the line ends in '\n'; NoBlockSkip writes all of it or nothing
            let line = record.to_line();
            if cx.local.telemetry.write(line.as_bytes()) < line.len() {
                RTT_DROPPED.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// RTT channel 0, once a second: frames, drops, overruns, cycles min/mean/max, misses.
    #[task(priority = 1, shared = [stats, counters])]
    async fn summary(mut cx: summary::Context) {
        loop {
            Mono::delay(MonoDuration::millis(1000)).await;
            let totals = cx.shared.counters.lock(|c| *c);
            let dropped = RTT_DROPPED.load(Ordering::Relaxed);
            let s = cx.shared.stats.lock(|w| w.close(totals, dropped));
            rtt_target::rprint!("{}", s.to_line());
        }
    }
}
