//! The `sppm-gpu` command line: render a scene file to PNG or EXR, and the subcommands beside
//! it (src/cli/, one file each).

mod cli;
mod view;

fn main() -> std::process::ExitCode {
    cli::main()
}
