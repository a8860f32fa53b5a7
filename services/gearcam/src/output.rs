//! What the commands print on standard output. A reader that stops early
//! (`gearcam jobs | head -1`, `| true`) is not an error and never a panic:
//! the rest of the output is dropped. Any other write error is said once on
//! standard error.

use std::io::{ErrorKind, Write};

/// Writes `text` to standard output.
pub fn emit(text: &str) {
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        if e.kind() != ErrorKind::BrokenPipe {
            eprintln!("gearcam: cannot write to standard output: {e}");
        }
    }
}

/// `println!` that survives a closed pipe ([`emit`]).
#[macro_export]
macro_rules! outln {
    () => {
        $crate::output::emit("\n")
    };
    ($($arg:tt)*) => {
        $crate::output::emit(&format!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` that survives a closed pipe ([`emit`]).
#[macro_export]
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::output::emit(&format!($($arg)*))
    };
}
