//! `alvs`: host tools for the attention-driven LPLC2 visuomotor system.
//! Run through the cargo alias: `cargo alvs <subcommand> --help`.
//!
//! The command line is [`cli`]; here it is parsed and run, and a failure becomes one line on
//! stderr and an exit code (2 for a bad command line, 1 for a failed run, or the status of a
//! child that has said why itself).

use std::process::ExitCode;

use clap::Parser;

use cli::{one_line, run, Cli, Exit};

mod cli;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => {
            // --help, --version
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("alvs: error: {}", one_line(&e));
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        // a closed pipe (`alvs replay clip.y8 | head`) is the reader's choice, not an error
        Err(e)
            if e.chain().any(|c| {
                c.downcast_ref::<std::io::Error>()
                    .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
            }) =>
        {
            ExitCode::SUCCESS
        }
        Err(e) => match e.downcast_ref::<Exit>() {
            Some(Exit(code)) => ExitCode::from(*code),
            None => {
                eprintln!("alvs: error: {e:#}");
                ExitCode::FAILURE
            }
        },
    }
}
