//! The command line: parse, run the command, map its error to an exit code (`error::exit`).

use clap::Parser;
use std::process::ExitCode;

use shadematrix::cli::{dispatch, Cli};
use shadematrix::error::exit;

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("error")).init();
    match dispatch(Cli::parse().command.unwrap_or_default()) {
        Ok(()) => ExitCode::from(exit::OK),
        Err(e) => {
            eprintln!("shadematrix: {e}");
            ExitCode::from(e.exit_code())
        }
    }
}
