use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    // Subcommands come before clap reads the render's own flags.
    match std::env::args().nth(1).as_deref() {
        Some("merge") => raytrace::farm::merge_main(),
        Some("fmt") => raytrace::fmt::main(),
        Some("lsp") => raytrace::lsp::main(),
        _ => render(),
    }
}

fn render() -> ExitCode {
    let args = raytrace::cli::Args::parse();
    // A signal while the image is being written would leave its temporary
    // file behind; the handler removes it and exits as a shell expects of
    // a program stopped by a signal (128 + its number).
    raytrace::signals::install(raytrace::output::remove_pending);
    match raytrace::run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            // Rendered whole, then written once: stderr is unbuffered, and a
            // snippet of a long line would otherwise cost a write per character.
            let text = format!("{:?}", failure.report);
            eprintln!("{text}");
            ExitCode::from(failure.exit as u8)
        }
    }
}
