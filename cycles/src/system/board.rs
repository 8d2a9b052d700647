//! The virtual Colias sense board: the firmware ELF from its reset vector on unicorn's
//! Cortex-M4, with the host doing what unicorn leaves out (exception entry and return, the
//! NVIC) and the peripheral models of this module behind the memory map.
//!
//! Time is the cycle model's pessimistic count at 180 MHz plus the exception entry/return
//! latencies and the time asleep in WFI; peripherals act through the event queue. The CPU runs
//! until the next event (or until an interrupt may preempt), the event is applied, and so on.
//! Before `freeze` the real core runs at 16 MHz: the boot's first instructions are counted
//! here as if at 180 MHz (a few hundred µs sooner than on the board).

use std::collections::HashMap;
use std::ops::Range;

use unicorn_engine::{HookType, MemType, Prot, RegisterARM, Unicorn};

use super::bus::{Peripherals, DCMI_CHANNEL, DCMI_STREAM, PERIPH, PERIPH_BB, SCS_PAGE};
use super::dcmi::{self, CameraTiming, DCMI_BASE};
use super::dma::Transfer;
use super::events::{Event, Queue};
use super::nvic::{self, HARD_FAULT};
use super::rcc;
use super::rtt::{self, Rtt};
use super::uart::UART4_BASE;
use crate::decode::{Decoded, Decoder};
use crate::elf::{self, Symbol};
use crate::emu::{self, cortex_m4, decode_at, emu, load, RegisterPage};
use crate::error::{Access, Error};
use crate::memory::{CCM, DWT_CYCCNT, DWT_PAGE, FLASH, SRAM};
use crate::timing::{FlashModel, Timing};

/// Cortex-M4 exception entry and return latency, and a tail-chain (ARM DDI 0439B 3.3.1).
const ENTRY_CYCLES: u64 = 12;
const RETURN_CYCLES: u64 = 12;
const TAIL_CHAIN_CYCLES: u64 = 6;
/// Exception return values live at the top of the address space (ARMv7-M ARM B1.5.8).
const EXC_RETURN_PAGE: u32 = 0xFFFF_F000;
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

/// A fault seen by a hook.
#[derive(Clone, Copy, Debug)]
enum Fault {
    Memory { access: Access, addr: u32, pc: u32 },
    Undefined { pc: u32 },
    Other { number: u32, pc: u32 },
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

    fn write_words(&mut self, addr: u32, words: &[u32]) -> Result<(), Error> {
        let bytes: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        self.uc
            .mem_write(addr.into(), &bytes)
            .map_err(|_| Error::Lockup {
                pc: 0,
                reason: format!("exception stack frame cannot be written at {addr:#010x}"),
            })
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

    fn preempting(&self) -> Result<Option<u16>, Error> {
        let basepri = self.reg(RegisterARM::BASEPRI)? as u8;
        let primask = self.reg(RegisterARM::PRIMASK)? & 1 != 0;
        let faultmask = self.reg(RegisterARM::FAULTMASK)? & 1 != 0;
        Ok(self
            .uc
            .get_data()
            .p
            .nvic
            .preempting(basepri, primask, faultmask))
    }

    /// Exception entry (B1.5.6): stacks the context (with the FP registers when CONTROL.FPCA
    /// says the context uses them), then runs the handler. `return_to`: the address to resume
    /// (the faulting instruction for a fault; else the current PC).
    fn enter(&mut self, exc: u16, return_to: Option<u32>) -> Result<(), Error> {
        self.account();
        let pc = match return_to {
            Some(pc) => pc,
            None => self.pc()?,
        };
        let control = self.reg(RegisterARM::CONTROL)?;
        if control & 2 != 0 {
            return Err(Error::Lockup {
                pc,
                reason: "Thread mode on the process stack is not modelled".into(),
            });
        }
        let fp = control & 4 != 0;
        let sp = self.reg(RegisterARM::SP)?;
        let size = if fp { 0x68 } else { 0x20 };
        let align = (sp >> 2) & 1;
        let frame = sp.wrapping_sub(size) & !(align << 2);
        let xpsr = (self.reg(RegisterARM::XPSR)? & !0x200) | align << 9 | 1 << 24;
        let mut words = vec![
            self.reg(RegisterARM::R0)?,
            self.reg(RegisterARM::R1)?,
            self.reg(RegisterARM::R2)?,
            self.reg(RegisterARM::R3)?,
            self.reg(RegisterARM::R12)?,
            self.reg(RegisterARM::LR)?,
            pc,
            xpsr,
        ];
        if fp {
            for i in 0..16 {
                words.push(self.reg(s_reg(i))?);
            }
            words.push(self.reg(RegisterARM::FPSCR)?);
            words.push(0);
        }
        let ccm_or_sram = |a: u32| CCM.contains(&a) || SRAM.contains(&a);
        if !ccm_or_sram(frame) || !ccm_or_sram(sp.wrapping_sub(1)) {
            return Err(Error::Lockup {
                pc,
                reason: format!(
                    "exception {exc} cannot stack its frame: SP {sp:#010x} (stack overflow)"
                ),
            });
        }
        self.write_words(frame, &words)?;
        let thread = self.uc.get_data().p.nvic.current() == 0;
        let exc_return = match (fp, thread) {
            (false, false) => 0xFFFF_FFF1,
            (false, true) => 0xFFFF_FFF9,
            (true, false) => 0xFFFF_FFE1,
            (true, true) => 0xFFFF_FFE9,
        };
        self.set(RegisterARM::SP, frame)?;
        self.set(RegisterARM::LR, exc_return)?;
        self.set(RegisterARM::CONTROL, control & !4)?;
        self.handler(exc)?;
        self.uc.get_data_mut().extra += ENTRY_CYCLES;
        Ok(())
    }

    /// Makes `exc` active and jumps to its handler.
    fn handler(&mut self, exc: u16) -> Result<(), Error> {
        let vector = self.read_u32(self.vector_table() + 4 * u32::from(exc))?;
        self.set(RegisterARM::IPSR, u32::from(exc))?;
        self.set(RegisterARM::PC, vector | 1)?;
        let st = self.uc.get_data_mut();
        st.p.nvic.activate(exc);
        st.timing.redirect();
        Ok(())
    }

    /// Exception return (B1.5.8), or a tail-chain into the next pending exception.
    fn exception_return(&mut self) -> Result<(), Error> {
        self.account();
        let exc_return = self.pc()? | 1;
        let st = self.uc.get_data_mut();
        if st.p.nvic.deactivate().is_none() {
            return Err(Error::Lockup {
                pc: exc_return,
                reason: "exception return with no active exception".into(),
            });
        }
        st.p.update_lines();
        if let Some(next) = self.preempting()? {
            self.set(RegisterARM::LR, exc_return)?;
            self.handler(next)?;
            self.uc.get_data_mut().extra += TAIL_CHAIN_CYCLES;
            return Ok(());
        }
        let sp = self.reg(RegisterARM::SP)?;
        let fp = exc_return & 0x10 == 0;
        let n = if fp { 26 } else { 8 };
        let bytes = self.read(sp, 4 * n)?;
        let w: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        for (r, v) in [
            RegisterARM::R0,
            RegisterARM::R1,
            RegisterARM::R2,
            RegisterARM::R3,
            RegisterARM::R12,
            RegisterARM::LR,
        ]
        .into_iter()
        .zip(&w)
        {
            self.set(r, *v)?;
        }
        if fp {
            for i in 0..16 {
                self.set(s_reg(i), w[8 + i])?;
            }
            self.set(RegisterARM::FPSCR, w[24])?;
        }
        let xpsr = w[7];
        let size = 4 * n as u32 + ((xpsr >> 9) & 1) * 4;
        self.set(RegisterARM::SP, sp + size)?;
        let control = self.reg(RegisterARM::CONTROL)?;
        self.set(
            RegisterARM::CONTROL,
            if fp { control | 4 } else { control & !4 },
        )?;
        self.set(RegisterARM::XPSR_NZCVQG, xpsr)?;
        self.set(RegisterARM::IPSR, xpsr & 0x1FF)?;
        self.set(RegisterARM::PC, w[6] | 1)?;
        let st = self.uc.get_data_mut();
        st.extra += RETURN_CYCLES;
        st.timing.redirect();
        Ok(())
    }

    /// A synchronous fault: HardFault (the configurable faults are not enabled by the firmware,
    /// so they escalate, B1.5.8), or a lockup when HardFault itself faults.
    fn fault(&mut self, fault: Fault) -> Result<(), Error> {
        let (pc, cfsr, what) = match fault {
            Fault::Memory { access, addr, pc } => (
                pc,
                1 << 9, // PRECISERR
                format!("{access} of unmapped address {addr:#010x}"),
            ),
            Fault::Undefined { pc } => (pc, 1 << 16, "undefined instruction".to_owned()), // UNDEFINSTR
            Fault::Other { number, pc } => (pc, 1 << 16, format!("CPU exception {number}")),
        };
        let st = self.uc.get_data_mut();
        if st.p.nvic.current() == HARD_FAULT || st.p.nvic.active().contains(&HARD_FAULT) {
            return Err(Error::Lockup {
                pc,
                reason: format!("{what} in the HardFault handler"),
            });
        }
        st.p.nvic.cfsr |= cfsr;
        st.p.nvic.hfsr |= 1 << 30; // FORCED
        self.sleeping = false;
        self.enter(HARD_FAULT, Some(pc))
    }
}

fn s_reg(i: usize) -> RegisterARM {
    const S: [RegisterARM; 16] = [
        RegisterARM::S0,
        RegisterARM::S1,
        RegisterARM::S2,
        RegisterARM::S3,
        RegisterARM::S4,
        RegisterARM::S5,
        RegisterARM::S6,
        RegisterARM::S7,
        RegisterARM::S8,
        RegisterARM::S9,
        RegisterARM::S10,
        RegisterARM::S11,
        RegisterARM::S12,
        RegisterARM::S13,
        RegisterARM::S14,
        RegisterARM::S15,
    ];
    S[i]
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

/// The board's memory map beyond flash, CCM and SRAM.
fn map_memory(uc: &mut Unicorn<'static, Sys>) -> Result<(), Error> {
    // ST's system memory and OTP/UID area: read-only zeros
    uc.mem_map(0x1FFF_0000, 0x1_0000, Prot::READ).map_err(emu)?;
    uc.mem_map(EXC_RETURN_PAGE.into(), 0x1000, Prot::READ | Prot::EXEC)
        .map_err(emu)?;
    let rw = Prot::READ | Prot::WRITE;
    // PPB as RAM except the DWT page and the SCS page, which are models
    uc.mem_map(0xE000_0000, u64::from(DWT_PAGE - 0xE000_0000), rw)
        .map_err(emu)?;
    uc.mem_map(
        u64::from(DWT_PAGE + 0x1000),
        u64::from(SCS_PAGE - DWT_PAGE - 0x1000),
        rw,
    )
    .map_err(emu)?;
    uc.mem_map(
        u64::from(SCS_PAGE + 0x1000),
        0xE010_0000 - u64::from(SCS_PAGE + 0x1000),
        rw,
    )
    .map_err(emu)?;
    uc.mmio_map(
        DWT_PAGE.into(),
        0x1000,
        Some(|uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize| {
            let st = uc.get_data_mut();
            if offset == u64::from(DWT_CYCCNT - DWT_PAGE) {
                return st.now() & 0xFFFF_FFFF;
            }
            st.dwt.read(offset, size)
        }),
        Some(
            |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize, value: u64| {
                uc.get_data_mut().dwt.write(offset, size, value);
            },
        ),
    )
    .map_err(emu)?;
    for (base, size) in [
        (SCS_PAGE, 0x1000u64),
        (PERIPH.start, u64::from(PERIPH.end - PERIPH.start)),
        (DCMI_BASE, 0x1000),
    ] {
        uc.mmio_map(
            base.into(),
            size,
            Some(move |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize| {
                u64::from(bus_read(uc.get_data_mut(), base + offset as u32, size))
            }),
            Some(
                move |uc: &mut Unicorn<'_, Sys>, offset: u64, size: usize, value: u64| {
                    bus_write(uc.get_data_mut(), base + offset as u32, size, value as u32);
                },
            ),
        )
        .map_err(emu)?;
    }
    // the peripheral bit-band alias
    uc.mmio_map(
        PERIPH_BB.into(),
        u64::from(PERIPH.end - PERIPH.start) * 32,
        Some(|uc: &mut Unicorn<'_, Sys>, offset: u64, _size: usize| {
            let (word, bit) = Peripherals::bit_band(PERIPH_BB + offset as u32);
            let st = uc.get_data_mut();
            let now = st.now();
            u64::from((st.p.read(word, now) >> bit) & 1)
        }),
        Some(
            |uc: &mut Unicorn<'_, Sys>, offset: u64, _size: usize, value: u64| {
                let (word, bit) = Peripherals::bit_band(PERIPH_BB + offset as u32);
                let st = uc.get_data_mut();
                let now = st.now();
                let old = st.p.read(word, now);
                let new = if value & 1 != 0 {
                    old | 1 << bit
                } else {
                    old & !(1 << bit)
                };
                bus_write(st, word, 4, new);
            },
        ),
    )
    .map_err(emu)?;
    Ok(())
}

fn bus_read(st: &mut Sys, addr: u32, size: usize) -> u32 {
    let now = st.now();
    let word = st.p.read(addr & !3, now);
    let shift = 8 * (addr & 3);
    let mask = if size >= 4 {
        u32::MAX
    } else {
        (1u32 << (8 * size)) - 1
    };
    (word >> shift) & mask
}

fn bus_write(st: &mut Sys, addr: u32, size: usize, value: u32) {
    let now = st.now();
    let aligned = addr & !3;
    let word = if size >= 4 {
        value
    } else {
        // a narrow write: the other bytes keep what a read returns (0 for the write-only
        // and write-1-to-clear registers)
        let shift = 8 * (addr & 3);
        let mask = ((1u32 << (8 * size)) - 1) << shift;
        (st.p.read(aligned, now) & !mask) | ((value << shift) & mask)
    };
    if aligned == UART4_BASE + 4 {
        st.log.uart_writes.push((now, value as u8));
    }
    if st.p.write(aligned, word, now, &mut st.events) {
        st.p.update_lines();
    }
    // the queue may hold an earlier event now, and an interrupt may be pending
    st.stop_at = st.stop_at.min(st.events.next_at());
    if st.p.nvic.any_pending() {
        st.force_stop = true;
    }
}

fn add_hooks(uc: &mut Unicorn<'static, Sys>) -> Result<(), Error> {
    uc.add_code_hook(1, 0, |uc: &mut Unicorn<'_, Sys>, addr: u64, size: u32| {
        let pc = addr as u32;
        if !uc.get_data().decoded.contains_key(&pc) {
            let d = decode_at(uc, &uc.get_data().decoder, addr, size);
            let text = d.text();
            let kind = if text.starts_with("wfi") || text.starts_with("wfe") {
                Kind::Sleep
            } else if text.starts_with("msr") || text.starts_with("cps") {
                Kind::Mask
            } else {
                Kind::Plain
            };
            uc.get_data_mut().decoded.insert(pc, (d, kind));
        }
        let st = uc.get_data_mut();
        let Some(&(d, kind)) = st.decoded.get(&pc) else {
            return;
        };
        if !st.timing.in_it_block()
            && (st.force_stop
                || st.now() >= st.stop_at
                || kind == Kind::Sleep
                || pc >= EXC_RETURN_PAGE)
        {
            let _ = uc.emu_stop();
            return;
        }
        st.timing.step(pc, &d);
        if kind == Kind::Mask && st.p.nvic.any_pending() {
            st.force_stop = true;
        }
    })
    .map_err(emu)?;

    uc.add_mem_hook(
        HookType::MEM_INVALID,
        1,
        0,
        |uc: &mut Unicorn<'_, Sys>, kind: MemType, addr: u64, _size: usize, _v: i64| {
            let access = match kind {
                MemType::READ_UNMAPPED | MemType::READ_PROT => Access::Read,
                MemType::WRITE_UNMAPPED | MemType::WRITE_PROT => Access::Write,
                _ => Access::Fetch,
            };
            let st = uc.get_data_mut();
            let pc = st.timing.pc();
            st.fault.get_or_insert(Fault::Memory {
                access,
                addr: addr as u32,
                pc,
            });
            false
        },
    )
    .map_err(emu)?;
    uc.add_intr_hook(|uc: &mut Unicorn<'_, Sys>, number: u32| {
        let pc = uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32;
        let st = uc.get_data_mut();
        if number == 8 {
            // EXCP_EXCEPTION_EXIT: a branch to an EXC_RETURN value in Handler mode
            st.exc_return = true;
        } else {
            st.fault.get_or_insert(Fault::Other { number, pc });
        }
        let _ = uc.emu_stop();
    })
    .map_err(emu)?;
    uc.add_insn_invalid_hook(|uc: &mut Unicorn<'_, Sys>| {
        let pc = uc.reg_read(RegisterARM::PC).unwrap_or(0) as u32;
        let st = uc.get_data_mut();
        st.fault.get_or_insert(Fault::Undefined { pc });
        false
    })
    .map_err(emu)?;
    Ok(())
}

#[cfg(test)]
mod tests;
