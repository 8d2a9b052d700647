//! The virtual Colias sense board: the firmware ELF from its reset vector on unicorn's
//! Cortex-M4, with the host doing what unicorn leaves out (exception entry and return, the
//! NVIC) and the peripheral models of this module behind the memory map.
//!
//! Time is the cycle model's pessimistic count at 180 MHz plus the exception entry/return
//! latencies and the time asleep in WFI; peripherals act through the event queue. The CPU runs
//! until the next event (or until an interrupt may preempt), the event is applied, and so on.
//! Before `freeze` the real core runs at 16 MHz: the boot's first instructions are counted
//! here as if at 180 MHz (a few hundred µs sooner than on the board).
//!
//! This file holds the board itself: its construction, power-on, resets and the run loop that
//! applies the events. Exception entry and return and the faults are in `board/exceptions.rs`,
//! the memory map and the peripherals' bus access in `board/memory_map.rs`, unicorn's hooks in
//! `board/hooks.rs`.

use std::collections::HashMap;
use std::ops::Range;

use unicorn_engine::{RegisterARM, Unicorn};

use super::bus::{Peripherals, DCMI_CHANNEL, DCMI_STREAM, PERIPH};
use super::dcmi::{self, CameraTiming};
use super::dma::Transfer;
use super::events::{Event, Queue};
use super::nvic;
use super::rcc;
use super::rtt::{self, Rtt};
use crate::decode::{Decoded, Decoder};
use crate::elf::{self, Symbol};
use crate::emu::{self, cortex_m4, emu, load, RegisterPage};
use crate::error::Error;
use crate::memory::{CCM, FLASH, SRAM};
use crate::timing::{FlashModel, Timing};

mod exceptions;
mod hooks;
mod memory_map;

use exceptions::{Fault, EXC_RETURN_PAGE};
use hooks::add_hooks;
use memory_map::map_memory;

/// The pattern the stack is painted with at power-on.
const STACK_PAINT: u32 = 0xDEAD_BEEF;

/// The camera's frame: 99x72 grey levels.
pub const WIDTH: usize = alvs_tasks::WIDTH;
pub const HEIGHT: usize = alvs_tasks::HEIGHT;

/// Supplies frame `n`'s 99x72 luma image when the sensor starts sending it.
pub type FrameSource = Box<dyn FnMut(u64) -> Vec<u8>>;

/// What the virtual board is built with.
#[derive(Clone, Debug)]
pub struct Config {
    pub camera: CameraTiming,
    /// An OV7670 answers on SCCB (false: the board without its camera).
    pub camera_present: bool,
    /// How often the host reads RTT, in cycles (a probe polls every few ms).
    pub rtt_poll_cycles: u64,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            camera: CameraTiming::default(),
            camera_present: true,
            rtt_poll_cycles: crate::CLOCK_HZ / 1000,
        }
    }
}

/// Why the board restarted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ResetCause {
    Watchdog,
    Software,
}

/// Instruction properties the run loop needs besides timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Plain,
    /// WFI/WFE: sleep until an interrupt.
    Sleep,
    /// MSR/CPS: BASEPRI, PRIMASK or FAULTMASK may change.
    Mask,
}

/// What the board recorded, for reports and tests.
#[derive(Clone, Debug, Default)]
pub struct Log {
    /// Cycle at which the DCMI finished a frame's window (FRAME), and the sensor's frame number.
    pub frames_captured: Vec<(u64, u64)>,
    /// Bytes written to UART4's DR, with the cycle of the write.
    pub uart_writes: Vec<(u64, u8)>,
    /// Resets after power-on.
    pub resets: Vec<(u64, ResetCause)>,
    /// Cycles spent in each exception (index = exception number, 0 = Thread mode).
    pub load: Vec<u64>,
    /// Cycles asleep in WFI.
    pub asleep: u64,
    /// Frames the sensor sent.
    pub frames_sent: u64,
}

struct Sys {
    decoder: Decoder,
    decoded: HashMap<u32, (Decoded, Kind)>,
    timing: Timing,
    /// Cycles outside instructions: exception latencies, sleep.
    extra: u64,
    events: Queue,
    /// The CPU stops before the first instruction at or after this cycle.
    stop_at: u64,
    /// Stop before the next instruction (an interrupt may preempt).
    force_stop: bool,
    exc_return: bool,
    fault: Option<Fault>,
    p: Peripherals,
    config: Config,
    frames: FrameSource,
    image: Vec<u8>,
    rtt: Rtt,
    log: Log,
    /// Camera stalls: no frame starts inside these cycle ranges.
    stalls: Vec<std::ops::Range<u64>>,
    /// The DMA is held off the bus (another master) inside these cycle ranges.
    dma_holds: Vec<std::ops::Range<u64>>,
    /// Frames the sensor cuts short: (frame, lines sent before VSYNC blanks).
    torn: Vec<(u64, u16)>,
    /// Cycle of the last load accounting.
    accounted: u64,
    dwt: RegisterPage,
}

impl Sys {
    fn now(&self) -> u64 {
        self.timing.counters.pessimistic() + self.extra
    }

    /// Schedules what runs whatever the MCU does (at power-on, again after a reset): the
    /// sensor's next frame start on its own frame clock, and the probe's next RTT poll.
    fn schedule_clocks(&mut self) {
        let now = self.now();
        let period = self.config.camera.frame_cycles;
        let first = self.config.camera.first_frame_at;
        let next = if now < first {
            first
        } else {
            first + (now - first).div_ceil(period) * period
        };
        let frame = (next - first) / period;
        self.events.schedule(next, Event::FrameStart { frame });
        self.events
            .schedule(now + self.config.rtt_poll_cycles, Event::RttPoll);
    }
}

/// The virtual board.
pub struct Board {
    uc: Unicorn<'static, Sys>,
    symbols: HashMap<String, Symbol>,
    sleeping: bool,
    /// The call stack's region: `_stack_end.._stack_start` of the ELF (memory.x), else all
    /// of CCM.
    stack: Range<u32>,
}

impl Board {
    /// Loads the firmware ELF and powers the board on (the CPU at its reset vector).
    pub fn new(elf_bytes: &[u8], config: Config, frames: FrameSource) -> Result<Board, Error> {
        Board::with_image(elf::parse(elf_bytes)?, config, frames)
    }

    /// A board whose flash holds `flash` from 0x0800_0000 (vector table first), for tests of
    /// the core with hand-written code.
    pub fn from_flash(flash: &[u8], config: Config, frames: FrameSource) -> Result<Board, Error> {
        let image = elf::Image {
            chunks: vec![elf::Chunk {
                what: "flash".into(),
                addr: FLASH.start,
                bytes: flash.to_vec(),
                zeros: 0,
            }],
            symbols: HashMap::new(),
            sections: Vec::new(),
        };
        Board::with_image(image, config, frames)
    }

    fn with_image(image: elf::Image, config: Config, frames: FrameSource) -> Result<Board, Error> {
        let rtt_block = image.symbols.get("_SEGGER_RTT").map_or(0, |s| s.value);
        let sys = Sys {
            decoder: Decoder::new().map_err(Error::Emulator)?,
            decoded: HashMap::new(),
            timing: Timing::new(FlashModel::default()),
            extra: 0,
            events: Queue::default(),
            stop_at: 0,
            force_stop: false,
            exc_return: false,
            fault: None,
            p: Peripherals::new(config.camera_present, rcc::CSR_PORRSTF | rcc::CSR_PINRSTF),
            config,
            frames,
            image: vec![128; WIDTH * HEIGHT],
            rtt: Rtt::new(rtt_block),
            log: Log {
                load: vec![0; usize::from(nvic::IRQ0 + nvic::IRQS)],
                ..Log::default()
            },
            stalls: Vec::new(),
            dma_holds: Vec::new(),
            torn: Vec::new(),
            accounted: 0,
            dwt: RegisterPage::new(0x1000),
        };
        let mut uc = cortex_m4(sys)?;
        map_memory(&mut uc)?;
        add_hooks(&mut uc)?;
        load(&mut uc, &image.chunks)?;
        // the stack's region (memory.x) painted, for the high-water mark
        let stack = image
            .stack()
            .filter(|r| CCM.start <= r.start && r.start < r.end && r.end <= CCM.end)
            .unwrap_or(CCM);
        emu::paint(&mut uc, stack.clone(), STACK_PAINT)?;
        let mut board = Board {
            uc,
            symbols: image.symbols,
            sleeping: false,
            stack,
        };
        board.power_on()?;
        Ok(board)
    }

    /// Cycles since power-on.
    pub fn now(&self) -> u64 {
        self.uc.get_data().now()
    }

    pub fn symbol(&self, name: &str) -> Option<u32> {
        self.symbols.get(name).map(Symbol::address)
    }

    /// Text of RTT up channel `i` so far (0 "log", 1 "telemetry").
    pub fn rtt(&self, i: usize) -> &str {
        self.uc.get_data().rtt.text(i)
    }

    /// RTT up channel `i` with the reads that moved its text to the host.
    pub fn rtt_channel(&self, i: usize) -> Option<&rtt::Channel> {
        self.uc.get_data().rtt.channels.get(i)
    }

    /// Types `bytes` into RTT down channel 0, as a probe's terminal does; the firmware reads
    /// them as it polls.
    pub fn rtt_type(&mut self, bytes: &[u8]) {
        self.uc.get_data_mut().rtt.type_in(bytes);
    }

    /// RTT up channels' names, as the firmware declared them.
    pub fn rtt_names(&self) -> Vec<String> {
        self.uc
            .get_data()
            .rtt
            .channels
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    /// Bytes that left UART4's TX pin, with the cycle each one's stop bit ended.
    pub fn uart_sent(&self) -> &[(u64, u8)] {
        &self.uc.get_data().p.uart.sent
    }

    pub fn log(&self) -> &Log {
        &self.uc.get_data().log
    }

    /// DCMI overruns and DMA view, for reports.
    pub fn dcmi_overruns(&self) -> u64 {
        self.uc.get_data().p.dcmi.overruns
    }

    /// The sensor sends no frame that would start inside `cycles` (a camera stall).
    pub fn stall_camera(&mut self, cycles: std::ops::Range<u64>) {
        self.uc.get_data_mut().stalls.push(cycles);
    }

    /// The DMA serves no request inside `cycles` (as if another bus master held it): the DCMI's
    /// FIFO fills and overruns.
    pub fn hold_dma(&mut self, cycles: std::ops::Range<u64>) {
        self.uc.get_data_mut().dma_holds.push(cycles);
    }

    /// The sensor sends only the first `lines` lines of frame `frame`, then blanks (a torn
    /// frame: VSYNC early).
    pub fn tear_frame(&mut self, frame: u64, lines: u16) {
        self.uc.get_data_mut().torn.push((frame, lines));
    }

    /// The deepest the stack (CCM, painted at power-on) has been since, in bytes below its top:
    /// every task and interrupt nesting included.
    pub fn stack_high_water(&self) -> Result<u32, Error> {
        emu::high_water(&self.uc, self.stack.clone(), STACK_PAINT)
    }

    /// Paints the free stack again (below SP; only in Thread mode, where nothing below SP is
    /// live), so that [`Board::stack_high_water`] measures from here on: e.g. the running
    /// tasks without the boot's self-benchmark. Returns false (and paints nothing) in Handler
    /// mode.
    pub fn repaint_stack(&mut self) -> Result<bool, Error> {
        if self.uc.get_data().p.nvic.current() != 0 {
            return Ok(false);
        }
        let sp = self.reg(RegisterARM::SP)? & !3;
        if !(self.stack.start..=self.stack.end).contains(&sp) {
            return Ok(false);
        }
        emu::paint(&mut self.uc, self.stack.start..sp, STACK_PAINT)?;
        Ok(true)
    }

    /// Reads memory (after a run, for tests).
    pub fn read(&self, addr: u32, len: usize) -> Result<Vec<u8>, Error> {
        emu::read(&self.uc, addr, len)
    }

    /// Raises the fault a `udf` would (the end of every panic) at the next instruction.
    pub fn inject_undefined_instruction(&mut self) -> Result<(), Error> {
        let pc = self.pc()?;
        self.fault(Fault::Undefined { pc })
    }

    /// The symbol of exception `exc`'s handler in the vector table ("Thread" for 0).
    pub fn exception_name(&self, exc: u16) -> String {
        if exc == 0 {
            return "Thread".into();
        }
        let vector = self
            .read_u32(self.vector_table() + 4 * u32::from(exc))
            .unwrap_or(0)
            & !1;
        self.symbols
            .iter()
            .filter(|(_, s)| s.function && s.address() == vector)
            .map(|(n, _)| n.clone())
            .min_by_key(|n| (n.starts_with('_'), n.len()))
            .unwrap_or_else(|| format!("exception {exc}"))
    }

    fn pc(&self) -> Result<u32, Error> {
        Ok(self.uc.reg_read(RegisterARM::PC).map_err(emu)? as u32)
    }

    fn reg(&self, r: RegisterARM) -> Result<u32, Error> {
        Ok(self.uc.reg_read(r).map_err(emu)? as u32)
    }

    fn set(&mut self, r: RegisterARM, v: u32) -> Result<(), Error> {
        self.uc.reg_write(r, v.into()).map_err(emu)
    }

    fn power_on(&mut self) -> Result<(), Error> {
        self.uc.get_data_mut().schedule_clocks();
        self.boot()
    }

    /// The core's reset: SP and PC from the vector table, registers to their reset values.
    fn boot(&mut self) -> Result<(), Error> {
        let table = self.vector_table();
        let sp = self.read_u32(table)?;
        let reset = self.read_u32(table + 4)?;
        self.set(RegisterARM::CONTROL, 0)?;
        self.set(RegisterARM::PRIMASK, 0)?;
        self.set(RegisterARM::BASEPRI, 0)?;
        self.set(RegisterARM::FAULTMASK, 0)?;
        self.set(RegisterARM::IPSR, 0)?;
        self.set(RegisterARM::SP, sp)?;
        self.set(RegisterARM::LR, 0xFFFF_FFFF)?;
        self.set(RegisterARM::PC, reset)?;
        self.uc.get_data_mut().timing.redirect();
        self.sleeping = false;
        Ok(())
    }

    /// A system reset (watchdog, SYSRESETREQ): peripherals and core to reset values; RAM keeps
    /// its contents (the firmware's startup initialises what it uses); the sensor keeps its
    /// frame clock.
    fn reset(&mut self, cause: ResetCause) -> Result<(), Error> {
        self.account();
        let st = self.uc.get_data_mut();
        let now = st.now();
        st.log.resets.push((now, cause));
        let flag = match cause {
            ResetCause::Watchdog => rcc::CSR_IWDGRSTF,
            ResetCause::Software => rcc::CSR_SFTRSTF,
        };
        let flags = st.p.reset_flags | flag;
        let uart_sent = std::mem::take(&mut st.p.uart.sent);
        let (captured, overruns) = (st.p.dcmi.frames_captured, st.p.dcmi.overruns);
        st.p = Peripherals::new(st.config.camera_present, flags);
        st.p.uart.sent = uart_sent;
        st.p.dcmi.frames_captured = captured;
        st.p.dcmi.overruns = overruns;
        st.force_stop = false;
        st.exc_return = false;
        st.fault = None;
        // the events of the old peripherals go; the sensor and the probe keep their clocks
        st.events.clear();
        st.schedule_clocks();
        self.boot()
    }

    fn vector_table(&self) -> u32 {
        let vtor = self.uc.get_data().p.nvic.vtor;
        // boot from flash: address 0 aliases the flash (RM0090 2.4)
        if vtor < FLASH.start {
            FLASH.start + vtor
        } else {
            vtor
        }
    }

    fn read_u32(&self, addr: u32) -> Result<u32, Error> {
        emu::read_u32(&self.uc, addr)
    }

    /// Adds the cycles since the last accounting to the running exception.
    fn account(&mut self) {
        let st = self.uc.get_data_mut();
        let now = st.now();
        let exc = usize::from(st.p.nvic.current());
        if let Some(l) = st.log.load.get_mut(exc) {
            *l += now - st.accounted;
        }
        st.accounted = now;
    }

    /// Runs the board for `cycles` more cycles.
    pub fn run_for(&mut self, cycles: u64) -> Result<(), Error> {
        let until = self.now() + cycles;
        self.run_until(until)
    }

    /// Runs the board until cycle `until`.
    pub fn run_until(&mut self, until: u64) -> Result<(), Error> {
        loop {
            self.apply_due_events()?;
            if self.uc.get_data().p.nvic.reset_requested {
                self.reset(ResetCause::Software)?;
                continue;
            }
            let now = self.now();
            if now >= until {
                self.account();
                return Ok(());
            }
            if let Some(exc) = self.preempting()? {
                self.sleeping = false;
                self.enter(exc, None)?;
                continue;
            }
            if self.sleeping {
                if self.uc.get_data().p.nvic.any_pending() {
                    self.sleeping = false;
                } else {
                    let st = self.uc.get_data_mut();
                    let wake = st.events.next_at().min(until);
                    st.extra += wake - now;
                    st.log.asleep += wake - now;
                    continue;
                }
            }
            self.execute(until)?;
        }
    }

    /// Runs instructions until a stop condition; then handles what stopped it.
    fn execute(&mut self, until: u64) -> Result<(), Error> {
        let pc = self.pc()?;
        {
            let st = self.uc.get_data_mut();
            st.stop_at = st.events.next_at().min(until);
            st.force_stop = false;
        }
        let result = self.uc.emu_start(u64::from(pc | 1), 0, 0, 0);
        let st = self.uc.get_data_mut();
        if let Some(fault) = st.fault.take() {
            return self.fault(fault);
        }
        if std::mem::take(&mut st.exc_return) {
            return self.exception_return();
        }
        if let Err(e) = result {
            return Err(Error::Emulator(format!("{e:?} at pc {:#010x}", self.pc()?)));
        }
        let pc = self.pc()?;
        if pc >= EXC_RETURN_PAGE {
            return self.exception_return();
        }
        let kind = self.uc.get_data().decoded.get(&pc).map(|d| d.1);
        if kind == Some(Kind::Sleep) && self.preempting()?.is_none() {
            // WFI executes: one cycle, then sleep unless something is pending
            let st = self.uc.get_data_mut();
            st.extra += 1;
            st.timing.redirect();
            self.set(RegisterARM::PC, pc + 2)?;
            self.sleeping = !self.uc.get_data().p.nvic.any_pending();
        }
        Ok(())
    }

    fn apply_due_events(&mut self) -> Result<(), Error> {
        loop {
            let st = self.uc.get_data_mut();
            let now = st.now();
            let Some((at, event)) = st.events.pop_due(now) else {
                return Ok(());
            };
            self.apply(at, event)?;
            self.uc.get_data_mut().p.update_lines();
        }
    }

    fn apply(&mut self, at: u64, event: Event) -> Result<(), Error> {
        let st = self.uc.get_data_mut();
        match event {
            Event::SysTickWrap { generation } => {
                if st.p.systick.wrap(generation, &mut st.events) {
                    st.p.nvic.set_pending(nvic::SYSTICK);
                }
            }
            Event::WatchdogExpired { generation } => {
                if st.p.iwdg.expired(generation) {
                    return self.reset(ResetCause::Watchdog);
                }
            }
            Event::UartShifted { generation } => {
                let cycles = st.p.uart_byte_cycles();
                st.p.uart.shifted(generation, at, cycles, &mut st.events);
            }
            Event::FrameStart { frame } => {
                let t = st.config.camera;
                st.events
                    .schedule(at + t.frame_cycles, Event::FrameStart { frame: frame + 1 });
                let stalled = st.stalls.iter().any(|r| r.contains(&at));
                if st.p.camera_alive() && !stalled {
                    st.log.frames_sent += 1;
                    let mut image = (st.frames)(frame);
                    image.resize(WIDTH * HEIGHT, 128);
                    st.image = image;
                    st.p.dcmi.frame_start();
                    let lines = st
                        .torn
                        .iter()
                        .find(|(f, _)| *f == frame)
                        .map_or(t.lines, |(_, n)| (*n).clamp(1, t.lines));
                    for line in 0..lines {
                        st.events
                            .schedule(at + t.line_end(line), Event::LineEnd { frame, line });
                    }
                    st.events
                        .schedule(at + t.line_end(lines - 1), Event::FrameEnd { frame });
                }
            }
            Event::LineEnd {
                frame: number,
                line,
            } => {
                let (x0, y0) = st.p.dcmi.window_origin();
                let clocks = usize::from(st.config.camera.line_clocks);
                let bytes =
                    dcmi::sensor_line(&st.image, WIDTH, HEIGHT, usize::from(line), clocks, x0, y0);
                let (words, frame) = st.p.dcmi.line_end(line, &bytes);
                let held = st.dma_holds.iter().any(|r| r.contains(&at));
                for w in words {
                    let reachable = |a: u32| SRAM.contains(&a) || PERIPH.contains(&a);
                    let st = self.uc.get_data_mut();
                    let transfer = if held {
                        Transfer::Refused
                    } else {
                        st.p.dma.request(DCMI_STREAM, DCMI_CHANNEL, reachable)
                    };
                    match transfer {
                        Transfer::Write(addr) => {
                            self.uc
                                .mem_write(addr.into(), &w.to_le_bytes())
                                .map_err(emu)?;
                        }
                        Transfer::Refused => st.p.dcmi.refused(),
                    }
                }
                if frame {
                    self.uc
                        .get_data_mut()
                        .log
                        .frames_captured
                        .push((at, number));
                }
            }
            Event::FrameEnd { .. } => st.p.dcmi.frame_end(),
            Event::RttPoll => {
                st.events
                    .schedule(at + st.config.rtt_poll_cycles, Event::RttPoll);
                let mut rtt = std::mem::take(&mut st.rtt);
                rtt.poll(&mut UcMemory(&mut self.uc), at);
                self.uc.get_data_mut().rtt = rtt;
            }
        }
        Ok(())
    }
}

/// RTT's view of the emulated memory.
struct UcMemory<'a, 'b>(&'a mut Unicorn<'b, Sys>);

impl rtt::Memory for UcMemory<'_, '_> {
    fn read(&self, addr: u32, len: usize) -> Option<Vec<u8>> {
        self.0.mem_read_as_vec(addr.into(), len).ok()
    }
    fn write_u32(&mut self, addr: u32, value: u32) -> bool {
        self.write(addr, &value.to_le_bytes())
    }
    fn write(&mut self, addr: u32, bytes: &[u8]) -> bool {
        self.0.mem_write(addr.into(), bytes).is_ok()
    }
}

#[cfg(test)]
mod tests;
