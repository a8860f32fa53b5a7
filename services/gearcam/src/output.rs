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

/// Unix milliseconds as `YYYY-MM-DD HH:MM:SS UTC` (proleptic Gregorian; days
/// to civil date after H. Hinnant, "chrono-Compatible Low-Level Date
/// Algorithms").
pub fn utc(ms: u64) -> String {
    let secs = ms / 1000;
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::utc;

    #[test]
    fn utc_formats_unix_milliseconds() {
        assert_eq!(utc(0), "1970-01-01 00:00:00 UTC");
        // 2000-02-29T12:34:56Z = 951 827 696 s (a leap day in a century leap year).
        assert_eq!(utc(951_827_696_000), "2000-02-29 12:34:56 UTC");
        // 2023-11-14T22:13:20Z = 1 700 000 000 s.
        assert_eq!(utc(1_700_000_000_999), "2023-11-14 22:13:20 UTC");
    }
}
