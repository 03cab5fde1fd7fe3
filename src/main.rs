use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = raytrace::cli::Args::parse();
    match raytrace::run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(report) => {
            eprintln!("{report:?}");
            ExitCode::FAILURE
        }
    }
}
