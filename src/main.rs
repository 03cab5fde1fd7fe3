use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = raytrace::cli::Args::parse();
    // Ctrl-C or SIGTERM while the image is being written would leave its
    // temporary file behind; the handler removes it and exits as a shell
    // expects of an interrupted program (128 + SIGINT).
    let _ = ctrlc::set_handler(|| {
        raytrace::output::remove_pending();
        std::process::exit(130);
    });
    match raytrace::run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(report) => {
            // Rendered whole, then written once: stderr is unbuffered, and a
            // snippet of a long line would otherwise cost a write per character.
            let text = format!("{report:?}");
            eprintln!("{text}");
            ExitCode::FAILURE
        }
    }
}
