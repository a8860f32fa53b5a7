//! The FANUC subset of `DIALECTS.md` (hobbing machine with the EGB), one line
//! at a time.
//!
//! Line 1 is `%`, line 2 the program number `O0001`–`O7999` with an optional
//! `(TITLE)`, and a line `%` closes the program (only blank lines may follow).
//! Every other line is empty, a `(comment)`, or one block: an optional
//! `N<n>`, then exactly one of a `#5nn=` assignment, `IF [a GE b] THEN #5nn=`
//! (a conditional assignment; `EQ NE LT LE GT GE`), `G81 T L [Q P]`, `G80`,
//! a dwell `G04 X`, an M function with an optional integer `S`, or a motion
//! block (`G00`–`G03`, `G90`, `G91`, `G98`, axis words, `R`, `F`), then an
//! optional `(comment)` that closes the line.

use super::expr::{self, Cursor, Num, Syntax};
use super::siemens::check_chars;
use super::{
    literal, numbered_lines, AxisName, AxisWord, Block, Distance, Interp, Motion, Op, Parsed,
};

/// Parses a FANUC program into `out`.
pub(super) fn parse(text: &str, out: &mut Parsed) {
    let mut closed: Option<u32> = None;
    let mut lines = 0;
    for (line, raw) in numbered_lines(text) {
        lines = line;
        let result = if let Some(end) = closed {
            if raw.trim().is_empty() {
                Ok(())
            } else {
                Err(format!("text after the closing % of line {end}"))
            }
        } else if line == 1 {
            if raw.trim_end() == "%" {
                Ok(())
            } else {
                Err("the first line is not %".into())
            }
        } else if line == 2 {
            program_number(raw)
        } else if raw.trim_end() == "%" {
            closed = Some(line);
            Ok(())
        } else {
            out.block(line, raw, body(raw), block);
            continue;
        };
        out.other(line, raw, result);
    }
    if lines == 0 {
        out.refuse(1, "", "the program is empty; it starts with %");
    } else if closed.is_none() {
        out.refuse(lines, "", "the program does not end with the % line");
    }
}

/// The block before its `(comment)`; the comment closes the line and holds no
/// parentheses.
fn strip_comment(text: &str) -> Result<&str, String> {
    let Some(open) = text.find('(') else {
        return if text.contains(')') {
            Err("a ) without its (".into())
        } else {
            Ok(text)
        };
    };
    let inner = text[open + 1..]
        .trim_end()
        .strip_suffix(')')
        .ok_or("a comment is not closed by ) at the end of the line")?;
    if inner.contains(['(', ')']) || text[..open].contains(')') {
        return Err("a comment holds parentheses".into());
    }
    Ok(&text[..open])
}

fn program_number(raw: &str) -> Result<(), String> {
    check_chars(raw)?;
    let body = strip_comment(raw)?.trim();
    let bad = || "the second line is not the program number O0001 to O7999".to_string();
    let digits = body.strip_prefix('O').ok_or_else(bad)?;
    match expr::small_uint(digits.as_bytes()) {
        Some(n) if digits.len() == 4 && (1..=7999).contains(&n) => Ok(()),
        _ => Err(bad()),
    }
}

/// G codes of the subset, by their two digits.
#[derive(Debug, Default)]
struct Codes {
    interp: Option<Interp>,
    distance: Option<Distance>,
    per_minute: bool,
    feed_code: Option<u8>,
    setup: super::Setup,
    dwell: bool,
    gear_on: bool,
    gear_off: bool,
    count: u8,
}

impl Codes {
    fn add(&mut self, digits: &[u8]) -> Result<(), String> {
        let g = |d: &[u8]| format!("G{}", String::from_utf8_lossy(d));
        let interp = |slot: &mut Option<Interp>, v| match slot {
            Some(old) if *old != v => Err(format!("{} conflicts with another G code", g(digits))),
            _ => {
                *slot = Some(v);
                Ok(())
            }
        };
        match digits {
            b"00" => interp(&mut self.interp, Interp::Rapid)?,
            b"01" => interp(&mut self.interp, Interp::Linear)?,
            b"02" => interp(&mut self.interp, Interp::ArcCw)?,
            b"03" => interp(&mut self.interp, Interp::ArcCcw)?,
            b"04" => self.dwell = true,
            b"80" => self.gear_off = true,
            b"81" => self.gear_on = true,
            b"90" | b"91" => {
                let d = if digits == b"90" {
                    Distance::Absolute
                } else {
                    Distance::Incremental
                };
                if self.distance.is_some_and(|old| old != d) {
                    return Err("G90 and G91 in one block".into());
                }
                self.distance = Some(d);
            }
            b"94" | b"98" => {
                self.per_minute = true;
                self.feed_code = Some(if digits == b"94" { 94 } else { 98 });
            }
            b"18" => self.setup.plane_zx = true,
            b"21" => self.setup.metric = true,
            [b'5', d @ b'4'..=b'9'] => self.setup.work_offset = Some(50 + (d - b'0')),
            _ => return Err(format!("{} is not in the FANUC subset", g(digits))),
        }
        self.count += 1;
        Ok(())
    }
}

/// Non-axis address words.
#[derive(Debug, Default)]
struct Words {
    s: Option<Num>,
    t: Option<Num>,
    l: Option<Num>,
    q: Option<Num>,
    p: Option<Num>,
}

fn number_word(
    c: &mut Cursor<'_>,
    slot: &mut Option<Num>,
    what: &str,
    decimals: u8,
    point: bool,
) -> Result<(), String> {
    if slot.is_some() {
        return Err(format!("{what} is written twice"));
    }
    let n = expr::number(c).ok_or_else(|| format!("{what} needs a number"))?;
    *slot = Some(literal(n, what, decimals, point)?);
    Ok(())
}

/// The block text of a line: without its comment and surrounding blanks
/// (empty for a comment or blank line).
fn body(raw: &str) -> Result<&str, String> {
    check_chars(raw)?;
    Ok(strip_comment(raw)?.trim_matches([' ', '\t']))
}

/// `5nn=value` after the `#`, to the end of the block.
fn assignment(c: &mut Cursor<'_>) -> Result<(u16, expr::NcValue), String> {
    let param = expr::macro_index(c.digits()).ok_or("macro variables are #500 to #999")?;
    c.skip_spaces();
    if !c.eat(b'=') {
        return Err("an assignment is #5nn=value".into());
    }
    c.skip_spaces();
    let value = expr::expression(c, Syntax::Fanuc)?;
    if let Some(n) = value.literal() {
        literal(n, "the value", 6, n.point)?;
    }
    c.skip_spaces();
    if !c.at_end() {
        return Err("unexpected text after the assignment".into());
    }
    Ok((param, value))
}

/// Parses a line's non-empty block text into `b`.
fn block(body: &str, b: &mut Block) -> Result<(), String> {
    let mut c = Cursor::new(body);
    let number = super::block_number(&mut c)?;
    c.skip_spaces();
    if c.at_end() {
        return Err("a block number without a block".into());
    }
    b.number = number;
    if c.eat_keyword("IF") {
        c.skip_spaces();
        if !c.eat(b'[') {
            return Err("IF is followed by its condition in [ ]".into());
        }
        c.skip_spaces();
        let cond = expr::condition(&mut c, Syntax::Fanuc)?;
        c.skip_spaces();
        if !c.eat(b']') {
            return Err("the condition of IF is not closed by ]".into());
        }
        c.skip_spaces();
        if !c.eat_keyword("THEN") {
            return Err(
                "IF [..] is followed by THEN and one assignment (GOTO is outside the subset)"
                    .into(),
            );
        }
        c.skip_spaces();
        if !c.eat(b'#') {
            return Err("THEN is followed by one #5nn= assignment".into());
        }
        let (param, value) = assignment(&mut c)?;
        b.op = Op::AssignIf { cond, param, value };
        return Ok(());
    }
    if c.eat(b'#') {
        let (param, value) = assignment(&mut c)?;
        b.op = Op::Assign { param, value };
        return Ok(());
    }
    let mut g = Codes::default();
    let mut m: Option<u16> = None;
    let mut w = Words::default();
    b.op = Op::Motion(Motion::default());
    let Op::Motion(motion) = &mut b.op else {
        return Err("a motion block could not be built".into());
    };
    loop {
        c.skip_spaces();
        let Some(letter) = c.peek() else { break };
        c.bump();
        match letter {
            b'G' => g.add(c.digits())?,
            b'M' => {
                let code = expr::small_uint(c.digits())
                    .filter(|n| *n <= 999)
                    .ok_or("an M function has 1 to 3 digits")?;
                if m.replace(code as u16).is_some() {
                    return Err("two M functions in one block".into());
                }
            }
            b'F' => number_word(&mut c, &mut motion.feed, "F", 3, true)?,
            b'R' => number_word(&mut c, &mut motion.radius, "R", 3, true)?,
            b'S' => number_word(&mut c, &mut w.s, "S", 0, false)?,
            b'T' => number_word(&mut c, &mut w.t, "T", 0, false)?,
            b'L' => number_word(&mut c, &mut w.l, "L", 0, false)?,
            b'Q' => number_word(&mut c, &mut w.q, "Q", 3, true)?,
            b'P' => number_word(&mut c, &mut w.p, "P", 4, true)?,
            b'X' | b'Y' | b'Z' | b'A' | b'B' | b'C' | b'U' | b'V' | b'W' => {
                let axis = AxisName::new(&[letter]).ok_or("an axis letter is not valid")?;
                let value = expr::operand(&mut c, Syntax::Fanuc)?;
                if let Some(n) = value.literal() {
                    literal(n, axis.as_str(), 4, true)?;
                }
                motion.push(AxisWord { axis, value })?;
            }
            _ => {
                return Err(format!(
                    "{} is not an address of the FANUC subset",
                    char::from(letter)
                ))
            }
        }
    }
    classify(g, m, w, &mut b.op)
}

/// Which of the block shapes the words make: the motion block read into
/// `slot` stays, or becomes the shape's operation.
fn classify(g: Codes, m: Option<u16>, w: Words, slot: &mut Op) -> Result<(), String> {
    let Op::Motion(motion) = slot else {
        return Err("a motion block could not be built".into());
    };
    let no_motion = motion.words().is_empty() && motion.feed.is_none() && motion.radius.is_none();
    let no_words =
        w.s.is_none() && w.t.is_none() && w.l.is_none() && w.q.is_none() && w.p.is_none();
    if g.gear_on {
        return match (g.count, m, no_motion, w) {
            (
                1,
                None,
                true,
                Words {
                    s: None,
                    t: Some(teeth),
                    l: Some(starts),
                    q,
                    p,
                },
            ) => {
                *slot = Op::FanucGearOn {
                    teeth,
                    starts,
                    module: q,
                    helix: p,
                };
                Ok(())
            }
            _ => Err("the EGB is switched on by G81 T_ L_ [Q_ P_] alone".into()),
        };
    }
    if g.gear_off {
        return if g.count == 1 && m.is_none() && no_motion && no_words {
            *slot = Op::GearOff { following: None };
            Ok(())
        } else {
            Err("G80 stands alone".into())
        };
    }
    if g.dwell {
        return match motion.words() {
            [AxisWord { axis, value }]
                if g.count == 1
                    && m.is_none()
                    && no_words
                    && motion.feed.is_none()
                    && motion.radius.is_none()
                    && axis.is("X") =>
            {
                let n = value.literal().ok_or("the dwell time is a number")?;
                if n.value < 0.0 {
                    return Err("the dwell time is negative".into());
                }
                *slot = Op::Dwell {
                    seconds: literal(n, "the dwell time X", 3, true)?,
                };
                Ok(())
            }
            _ => Err("a dwell is G04 Xseconds alone".into()),
        };
    }
    if let Some(code) = m {
        let only_s = w.t.is_none() && w.l.is_none() && w.q.is_none() && w.p.is_none();
        if g.count != 0 || !no_motion || !only_s {
            return Err("an M function stands alone, or with S".into());
        }
        if w.s.is_some_and(|s| s.value < 0.0) {
            return Err("the speed S is negative".into());
        }
        *slot = Op::MCode { code, speed: w.s };
        return Ok(());
    }
    if !no_words {
        return Err("S, T, L, Q and P belong to M or G81 blocks".into());
    }
    let arc = matches!(g.interp, Some(Interp::ArcCw | Interp::ArcCcw));
    motion.interp = g.interp;
    motion.distance = g.distance;
    motion.per_minute = g.per_minute;
    motion.feed_code = g.feed_code;
    motion.setup = g.setup;
    if g.count == 0 && motion.words().is_empty() {
        return Err("a block with nothing to do".into());
    }
    match (arc, motion.radius.is_some()) {
        (true, false) => Err("an arc is programmed with its radius R".into()),
        (false, true) => Err("R is the radius of a G02/G03 arc".into()),
        (true, true) if motion.words().is_empty() => Err("an arc needs its end point".into()),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(line: &str) -> Result<Op, String> {
        crate::one_block(line, body, block)
    }

    #[test]
    fn conditional_assignment() {
        let Op::AssignIf { cond, param, value } =
            one("IF [#525 GE #523*#524] THEN #525=0 (START AGAIN)").unwrap()
        else {
            panic!()
        };
        assert_eq!((cond.rel, param), (expr::Rel::Ge, 525));
        assert_eq!(value.literal().unwrap().value, 0.0);
        let mut r = [0.0; expr::PARAMS];
        (r[523], r[524], r[525]) = (4.0, 6.0, 24.0);
        assert!(cond.eval(&r).unwrap());
        for bad in [
            "IF [#525 GE 4] GOTO 10",
            "IF [#525 >= 4] THEN #525=0",
            "IF [#525GE 4] THEN #525=0",
            "IF #525 GE 4 THEN #525=0",
            "IF [#525 GE 4] THEN G00 X1.0",
            "IF [#525 GE 4 THEN #525=0",
        ] {
            assert!(one(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn blocks_of_the_subset() {
        let Op::Motion(m) = one("N10 G00 G90 X174.05 Z82.0 A2.3715").unwrap() else {
            panic!()
        };
        assert_eq!(m.interp, Some(Interp::Rapid));
        assert_eq!(m.words().len(), 3);
        let Op::FanucGearOn {
            teeth,
            starts,
            module,
            helix,
        } = one("N160 G81 T25 L1 Q3.0 P15.0 (EGB ON)").unwrap()
        else {
            panic!()
        };
        assert_eq!((teeth.value, starts.value), (25.0, 1.0));
        assert_eq!(module.map(|q| q.value), Some(3.0));
        assert_eq!(helix.map(|p| p.value), Some(15.0));
        assert!(matches!(
            one("N170 M03 S358 (HOB ON, RPM)").unwrap(),
            Op::MCode {
                code: 3,
                speed: Some(_)
            }
        ));
        assert!(matches!(
            one("#526=FIX[#525/#523]").unwrap(),
            Op::Assign { param: 526, .. }
        ));
        let Op::Motion(m) = one("N190 G00 G90 X82.5 Y[#520+#522*#527]").unwrap() else {
            panic!()
        };
        assert!(m.words()[1].value.literal().is_none());
        let Op::Motion(m) = one("N205 G01 G91 Y9.433 C5.601 F100.0").unwrap() else {
            panic!()
        };
        assert_eq!(m.distance, Some(Distance::Incremental));
        assert!(matches!(
            one("N215 G04 X2.0 (DWELL, S)").unwrap(),
            Op::Dwell { .. }
        ));
        assert!(matches!(
            one("N250 G80 (EGB OFF)").unwrap(),
            Op::GearOff { .. }
        ));
        let Op::Motion(m) = one("N210 G02 X81.27 Z50.0 R140.0 F19.099").unwrap() else {
            panic!()
        };
        assert_eq!(m.radius.map(|r| r.value), Some(140.0));
        assert_eq!(body("(JOB SP-2002)"), Ok(""));
    }

    /// Regression: `O!` on the program-number line subtracted `b'0'` from `!`
    /// (found by the property test `random_text_never_panics`).
    #[test]
    fn program_number_with_a_non_digit_is_refused() {
        assert!(program_number("O!").is_err());
        assert!(program_number("O12!4").is_err());
        assert!(program_number("O0000").is_err());
        assert!(program_number("O8000").is_err());
        assert!(program_number("O2002 (SP-2002 HOBBING)").is_ok());
    }

    #[test]
    fn lines_outside_the_subset_are_refused() {
        for bad in [
            "N10 G00 X12",            // 0.012 mm on a FANUC: refused
            "N10 G0 X12.0",           // G codes have two digits
            "N10 M03 S358.0",         // S is whole rpm
            "N10 G81 T25.0 L1",       // T is a count
            "N10 G81 T25 L1 X1.0",    // G81 alone
            "N10 G80 X1.0",           // G80 alone
            "N10 G04 P2000",          // dwell in seconds with X
            "N10 G02 X1.0 Z1.0 F1.0", // arc without R
            "N10 G01 X1.0 R2.0",      // R without an arc
            "N10 G00 X1.0 (A (B) C)", // nested parentheses
            "N10 G00 X1.0 (OPEN",     // comment not closed
            "#100=1.0",               // common variables are not in the subset
            "N10 G65 P9000",          // macro call
            "N10 M03 M08",            // two M functions
            "N10 G90 G91 Y1.0",       // both
        ] {
            assert!(one(bad).is_err(), "{bad} should be refused");
        }
    }
}
