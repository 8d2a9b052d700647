//! A virtual Colias sense board: the unmodified firmware ELF from its reset vector, with a host
//! NVIC and peripheral models (RCC, GPIO with the OV7670's SCCB, DCMI, DMA2, UART4, IWDG,
//! SysTick, DWT, RTT) driven by an event queue in CPU cycles. See [`Board`].

mod board;
pub mod bus;
pub mod closed_loop;
pub mod dcmi;
pub mod dma;
pub mod embed_log;
pub mod events;
pub mod gpio;
pub mod iwdg;
pub mod nvic;
pub mod ov7670;
pub mod rcc;
pub mod report;
pub mod rtt;
pub mod systick;
pub mod uart;

pub use board::{Board, Config, FrameSource, Log, ResetCause, HEIGHT, WIDTH};
pub use dcmi::CameraTiming;
pub use report::Report;
