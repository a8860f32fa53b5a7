//! NC numbers as the programs write them.

/// Appends `v` as an NC number: `decimals` places, trailing zeros trimmed but
/// at least one digit after the point, never `-0` (what [`format_fixed`]
/// returns); false (and nothing appended) for NaN and infinities.
pub fn push_fixed(out: &mut String, v: f64, decimals: usize) -> bool {
    use std::fmt::Write;
    if !v.is_finite() {
        return false;
    }
    let start = out.len();
    let _ = write!(out, "{v:.decimals$}");
    if out[start..].contains('.') {
        let trimmed = out.trim_end_matches('0').len();
        out.truncate(trimmed);
        if out.ends_with('.') {
            out.push('0');
        }
    } else {
        out.push_str(".0");
    }
    if out[start..].starts_with('-') && out[start + 1..].bytes().all(|c| c == b'0' || c == b'.') {
        out.remove(start);
    }
    true
}

/// `v` as an NC number with `decimals` places (see [`push_fixed`]); `None`
/// for NaN and infinities.
pub fn format_fixed(v: f64, decimals: usize) -> Option<String> {
    let mut s = String::with_capacity(16);
    push_fixed(&mut s, v, decimals).then_some(s)
}
