use std::process::ExitCode;

use clap::CommandFactory;

fn main() -> ExitCode {
    // Mesa's Vulkan drivers probe for a Wayland display when the instance is created and, on
    // a headless machine without XDG_RUNTIME_DIR, print two "error:" lines that are not ours.
    if std::env::var_os("XDG_RUNTIME_DIR").is_none() {
        // SAFETY: no other thread exists yet, so nothing can read the environment meanwhile.
        unsafe { std::env::set_var("XDG_RUNTIME_DIR", std::env::temp_dir()) };
    }
    let matches = omnicloud::cli::Cli::command().get_matches();
    match omnicloud::cli::run(&matches) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", omnicloud::cli::error_message(&e));
            ExitCode::FAILURE
        }
    }
}
