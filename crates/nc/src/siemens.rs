//! The SINUMERIK 840D subset of `DIALECTS.md`, one line at a time.
//!
//! Line 1 is the file header `%_N_NAME_MPF`, line 2 `;$PATH=/_N_MPF_DIR`;
//! every other line is empty, a `;` comment, or one block: an optional
//! `N<n>`, then exactly one of an `R<n>=` assignment, `IF cond` / `ELSE` /
//! `ENDIF` (around assignments only; see the simulation), a gearbox call
//! (`EGDEF`, `EGON`, `EGONSYNE`, `EGOFS`, `EGDEL`), `MSG(...)`, an M function
//! with an optional `S=`, a dwell `G4 F=`, or a motion block (`G0`, `G1`,
//! `CIP`, `G90`, `G94`, `axis=value`, `I1=`, `K1=`, `F=`), then an optional
//! `;` comment.

use super::expr::{self, Cursor, Num, Syntax};
use super::{
    literal, numbered_lines, AxisName, AxisWord, Block, Distance, Interp, Lead, Motion, Op, Parsed,
    Setup,
};

/// Parses an 840D program into `out`.
pub(super) fn parse(text: &str, out: &mut Parsed) {
    let mut lines = 0;
    for (line, raw) in numbered_lines(text) {
        lines = line;
        match line {
            1 => out.other(line, raw, header(raw)),
            2 => out.other(line, raw, path(raw)),
            _ => out.block(line, raw, body(raw), block),
        }
    }
    if lines == 0 {
        out.refuse(
            1,
            "",
            "the program is empty; it starts with the header %_N_NAME_MPF",
        );
    } else if lines == 1 {
        out.refuse(2, "", "the second line ;$PATH=/_N_MPF_DIR is missing");
    }
}

fn header(raw: &str) -> Result<(), String> {
    let name = raw
        .trim_end()
        .strip_prefix("%_N_")
        .and_then(|r| r.strip_suffix("_MPF"))
        .ok_or("the first line is not the file header %_N_NAME_MPF")?;
    gearcam_proto::naming::check_name_840d(name)
        .map_err(|e| format!("the program name in the header is not valid: {e}"))
}

fn path(raw: &str) -> Result<(), String> {
    if raw.trim_end() == ";$PATH=/_N_MPF_DIR" {
        Ok(())
    } else {
        Err("the second line is not ;$PATH=/_N_MPF_DIR".into())
    }
}

/// Printable ASCII (and tabs) only.
pub(super) fn check_chars(text: &str) -> Result<(), String> {
    // No early exit, so that the loop vectorises: lines are short and valid.
    let bad = text.bytes().fold(false, |bad, b| {
        bad | ((b < b' ' && b != b'\t') | (b > b'~'))
    });
    if !bad {
        Ok(())
    } else {
        Err("the line holds characters outside printable ASCII".into())
    }
}

/// The block before its `;` comment (a `;` inside a `"..."` string is text).
fn strip_comment(text: &str) -> &str {
    let b = text.as_bytes();
    match b.iter().position(|&c| c == b';') {
        None => return text,
        Some(i) if !b[..i].contains(&b'"') => return &text[..i],
        Some(_) => {}
    }
    let mut quoted = false;
    for (i, b) in text.bytes().enumerate() {
        match b {
            b'"' => quoted = !quoted,
            b';' if !quoted => return &text[..i],
            _ => {}
        }
    }
    text
}

/// The block text of a line: without its comment and surrounding blanks
/// (empty for a comment or blank line).
fn body(raw: &str) -> Result<&str, String> {
    check_chars(raw)?;
    Ok(strip_comment(raw).trim_matches([' ', '\t']))
}

/// Parses a line's non-empty block text into `b`.
fn block(body: &str, b: &mut Block) -> Result<(), String> {
    let mut c = Cursor::new(body);
    let number = super::block_number(&mut c)?;
    if number.is_some() && !c.skip_spaces() {
        return Err("the block number is not followed by a space".into());
    }
    if c.at_end() {
        return Err("a block number without a block".into());
    }
    b.number = number;
    op(&mut c, &mut b.op)?;
    c.skip_spaces();
    if !c.at_end() {
        return Err("unexpected text after the block".into());
    }
    Ok(())
}

/// Parses the block's operation into `slot`.
fn op(c: &mut Cursor<'_>, slot: &mut Op) -> Result<(), String> {
    if c.eat_keyword("IF") {
        if !c.skip_spaces() {
            return Err("IF is followed by a space and its condition".into());
        }
        *slot = Op::If(expr::condition(c, Syntax::Siemens)?);
        return Ok(());
    }
    if c.eat_keyword("ELSE") {
        *slot = Op::Else;
        return Ok(());
    }
    if c.eat_keyword("ENDIF") {
        *slot = Op::EndIf;
        return Ok(());
    }
    match (c.peek(), c.peek_at(1)) {
        (Some(b'E'), Some(b'G')) | (Some(b'M'), Some(b'S')) => *slot = call(c)?,
        (Some(b'M'), Some(b'0'..=b'9')) => *slot = mcode(c)?,
        (Some(b'R'), Some(b'0'..=b'9')) if assignment(c, slot)? => {}
        _ => motion(c, slot)?,
    }
    Ok(())
}

/// `R<n>=expr`, if the block is one.
fn assignment(c: &mut Cursor<'_>, slot: &mut Op) -> Result<bool, String> {
    let start = c.i;
    c.bump();
    let digits = c.digits();
    if !c.eat(b'=') {
        c.i = start;
        return Ok(false);
    }
    let param = expr::param_index(digits).ok_or("R parameters are R0 to R999")?;
    let value = expr::expression(c, Syntax::Siemens)?;
    if let Some(n) = value.literal() {
        literal(n, "the value", 6, n.point)?;
    }
    *slot = Op::Assign { param, value };
    Ok(true)
}

/// A gearbox call or `MSG`.
fn call(c: &mut Cursor<'_>) -> Result<Op, String> {
    if c.eat_str("EGDEF(") {
        return egdef(&args(c)?);
    }
    if c.eat_str("EGONSYNE(") {
        return egonsyne(&args(c)?);
    }
    if c.eat_str("EGON(") {
        return egon(&args(c)?);
    }
    if c.eat_str("EGOFS(") {
        return Ok(Op::GearOff {
            following: Some(single_axis(&args(c)?, "EGOFS")?),
        });
    }
    if c.eat_str("EGDEL(") {
        return Ok(Op::GearDelete {
            following: single_axis(&args(c)?, "EGDEL")?,
        });
    }
    if c.eat_str("MSG(") {
        return match args(c)?.as_slice() {
            [] | [Arg::Str(_)] => Ok(Op::Message),
            _ => Err("MSG takes one quoted text or nothing".into()),
        };
    }
    Err("a gearbox call or MSG is malformed".into())
}

/// True at the end or after at least one space.
fn separated(c: &mut Cursor<'_>) -> bool {
    c.at_end() || c.skip_spaces()
}

fn mcode(c: &mut Cursor<'_>) -> Result<Op, String> {
    c.bump();
    let code = expr::small_uint(c.digits())
        .filter(|n| *n <= 999)
        .ok_or("an M function has at most 3 digits")? as u16;
    if !separated(c) {
        return Err("the M function is not followed by a space".into());
    }
    let mut speed = None;
    if c.eat_str("S=") {
        let n = expr::number(c).ok_or("S= needs a number")?;
        if n.value < 0.0 {
            return Err("the speed S is negative".into());
        }
        speed = Some(literal(n, "the speed S", 3, true)?);
    }
    Ok(Op::MCode { code, speed })
}

/// Sets a modal code once per block.
fn set<T: PartialEq + Copy>(slot: &mut Option<T>, v: T, word: &str) -> Result<(), String> {
    match slot {
        Some(old) if *old != v => Err(format!("{word} conflicts with another code of the block")),
        _ => {
            *slot = Some(v);
            Ok(())
        }
    }
}

/// A literal number word: `F=`, `I1=`, `K1=`.
fn number_word(c: &mut Cursor<'_>, what: &str, slot: &mut Option<Num>) -> Result<(), String> {
    if slot.is_some() {
        return Err(format!("{what} is written twice"));
    }
    let n = expr::number(c).ok_or_else(|| format!("{what} needs a number"))?;
    *slot = Some(literal(n, what, 3, true)?);
    Ok(())
}

/// Words that are not axis names.
fn reserved(id: &[u8]) -> bool {
    matches!(
        id,
        b"F" | b"S" | b"I1" | b"K1" | b"CIP" | b"MSG" | b"IF" | b"ELSE" | b"ENDIF"
    ) || (matches!(id[0], b'N' | b'G' | b'M' | b'R')
        && id.len() > 1
        && id[1..].iter().all(u8::is_ascii_digit))
}

/// A motion block or a dwell, built in `slot`.
fn motion(c: &mut Cursor<'_>, slot: &mut Op) -> Result<(), String> {
    *slot = Op::Motion(Motion::default());
    let Op::Motion(m) = slot else {
        return Err("a motion block could not be built".into());
    };
    let mut dwell = false;
    let (mut via_x, mut via_z) = (None, None);
    loop {
        c.skip_spaces();
        if c.at_end() {
            break;
        }
        let id = c.ident();
        match id {
            b"" => return Err("a word is malformed".into()),
            b"G0" => set(&mut m.interp, Interp::Rapid, "G0")?,
            b"G1" => set(&mut m.interp, Interp::Linear, "G1")?,
            b"CIP" => set(&mut m.interp, Interp::CircleVia, "CIP")?,
            b"G90" => set(&mut m.distance, Distance::Absolute, "G90")?,
            b"G94" => {
                m.per_minute = true;
                m.feed_code = Some(94);
            }
            b"G71" => m.setup.metric = true,
            b"DIAMOF" => m.setup.radius_x = true,
            [b'G', b'5', d @ b'4'..=b'9'] => m.setup.work_offset = Some(50 + (d - b'0')),
            b"G4" => dwell = true,
            _ if !c.eat(b'=') => {
                return Err(format!(
                    "{} is not a word of the 840D subset",
                    String::from_utf8_lossy(id)
                ))
            }
            b"F" => number_word(c, "F", &mut m.feed)?,
            b"I1" => number_word(c, "I1", &mut via_x)?,
            b"K1" => number_word(c, "K1", &mut via_z)?,
            _ => {
                let axis = AxisName::new(id).filter(|_| !reserved(id)).ok_or_else(|| {
                    format!("{} is not an axis name", String::from_utf8_lossy(id))
                })?;
                let value = expr::expression(c, Syntax::Siemens)?;
                if let Some(n) = value.literal() {
                    literal(n, axis.as_str(), 4, true)?;
                }
                m.push(AxisWord { axis, value })?;
            }
        }
        if !separated(c) {
            return Err("words are separated by spaces".into());
        }
    }
    if dwell {
        return match (&*m, m.feed) {
            (
                Motion {
                    interp: None,
                    distance: None,
                    per_minute: false,
                    setup:
                        Setup {
                            metric: false,
                            work_offset: None,
                            radius_x: false,
                            plane_zx: false,
                        },
                    ..
                },
                Some(seconds),
            ) if m.words().is_empty() && via_x.is_none() && via_z.is_none() => {
                *slot = Op::Dwell { seconds };
                Ok(())
            }
            _ => Err("a dwell is G4 F=seconds alone".into()),
        };
    }
    match (via_x, via_z) {
        (Some(x), Some(z)) if m.interp == Some(Interp::CircleVia) => m.via = Some((x, z)),
        (None, None) if m.interp == Some(Interp::CircleVia) => {
            return Err("CIP needs its intermediate point I1= K1=".into())
        }
        (None, None) => {}
        _ => return Err("I1= and K1= go together, in a CIP block".into()),
    }
    if m.interp == Some(Interp::CircleVia) && m.words().is_empty() {
        return Err("CIP needs its end point".into());
    }
    Ok(())
}

/// One argument of a gearbox call.
#[derive(Debug, Clone, Copy)]
enum Arg<'a> {
    Axis(AxisName),
    Str(&'a [u8]),
    Num(Num),
}

/// Arguments after `NAME(` up to and with the `)`.
fn args<'a>(c: &mut Cursor<'a>) -> Result<Vec<Arg<'a>>, String> {
    let mut v = Vec::new();
    c.skip_spaces();
    if c.eat(b')') {
        return Ok(v);
    }
    loop {
        c.skip_spaces();
        let a = match c.peek() {
            Some(b'"') => {
                c.bump();
                let start = c.i;
                while c.peek().is_some_and(|b| b != b'"') {
                    c.bump();
                }
                let s = c.since(start);
                if !c.eat(b'"') {
                    return Err("a quoted text is not closed".into());
                }
                Arg::Str(s)
            }
            Some(b'-' | b'+' | b'0'..=b'9') => {
                Arg::Num(expr::number(c).ok_or("a number argument is malformed")?)
            }
            Some(b) if b.is_ascii_alphabetic() => {
                Arg::Axis(AxisName::new(c.ident()).ok_or("an axis name is not valid")?)
            }
            _ => return Err("an argument is missing".into()),
        };
        v.push(a);
        if v.len() > 32 {
            return Err("too many arguments".into());
        }
        c.skip_spaces();
        if c.eat(b')') {
            return Ok(v);
        }
        if !c.eat(b',') {
            return Err("arguments are separated by commas".into());
        }
    }
}

fn single_axis(args: &[Arg<'_>], call: &str) -> Result<AxisName, String> {
    match args {
        [Arg::Axis(a)] => Ok(*a),
        _ => Err(format!("{call} takes the following axis alone")),
    }
}

/// A whole-number argument.
fn int(a: &Arg<'_>, what: &str) -> Result<i64, String> {
    match a {
        Arg::Num(n) => literal(*n, what, 0, false)?
            .integer()
            .ok_or_else(|| format!("{what} is too large")),
        _ => Err(format!("{what} must be a whole number")),
    }
}

fn axis(a: &Arg<'_>, what: &str) -> Result<AxisName, String> {
    match a {
        Arg::Axis(x) => Ok(*x),
        _ => Err(format!("{what} must be an axis name")),
    }
}

fn text(a: &Arg<'_>, want: &str) -> Result<(), String> {
    match a {
        Arg::Str(s) if *s == want.as_bytes() => Ok(()),
        _ => Err(format!("\"{want}\" is expected here")),
    }
}

/// `EGDEF(following, leading, type, ...)`: one to five leading axes, type 0 or 1.
fn egdef(args: &[Arg<'_>]) -> Result<Op, String> {
    let (Some(first), rest) = (args.first(), args.get(1..).unwrap_or_default()) else {
        return Err("EGDEF needs the following axis".into());
    };
    if rest.is_empty() || rest.len() % 2 != 0 || rest.len() > 10 {
        return Err(
            "EGDEF takes the following axis, then one to five (leading axis, type) pairs".into(),
        );
    }
    let mut leading = Vec::with_capacity(rest.len() / 2);
    for pair in rest.chunks_exact(2) {
        let t = int(&pair[1], "the coupling type")?;
        if !(0..=1).contains(&t) {
            return Err("the coupling type is 0 or 1".into());
        }
        leading.push((axis(&pair[0], "a leading axis")?, t));
    }
    Ok(Op::GearDefine {
        following: axis(first, "the following axis")?,
        leading,
    })
}

/// A (leading, num, den) triple; the hob's ratio is whole numbers, a factor
/// has a decimal point and up to 6 decimals with denominator 1.
fn triple(t: &[Arg<'_>], hob: bool, position: Option<Num>) -> Result<Lead, String> {
    let [a, num, den] = t else {
        return Err("a leading axis needs its numerator and denominator".into());
    };
    let axis = axis(a, "a leading axis")?;
    let num = match num {
        Arg::Num(n) if hob => literal(*n, "the hob ratio numerator", 0, false)?,
        Arg::Num(n) => literal(*n, "a coupling factor", 6, true)?,
        _ => return Err("a coupling numerator must be a number".into()),
    };
    let den_value = int(den, "a coupling denominator")?;
    if den_value == 0 {
        return Err("a coupling denominator is 0".into());
    }
    let Arg::Num(den) = den else {
        return Err("a coupling denominator must be a number".into());
    };
    Ok(Lead {
        axis,
        position,
        num,
        den: *den,
    })
}

fn leads(rest: &[Arg<'_>], first: Option<Lead>) -> Result<Vec<Lead>, String> {
    if rest.len() % 3 != 0 {
        return Err("each leading axis needs its numerator and denominator".into());
    }
    let mut out = Vec::with_capacity(rest.len() / 3 + 1);
    out.extend(first);
    for t in rest.chunks_exact(3) {
        out.push(triple(t, out.is_empty(), None)?);
    }
    if out.is_empty() || out.len() > 5 {
        return Err("a gearbox has one to five leading axes".into());
    }
    Ok(out)
}

/// `EGON(following, "FINE", leading, num, den, ...)`.
fn egon(args: &[Arg<'_>]) -> Result<Op, String> {
    let [f, mode, rest @ ..] = args else {
        return Err("EGON takes the following axis, \"FINE\" and the leading axes".into());
    };
    text(mode, "FINE")?;
    Ok(Op::GearOn {
        sync: false,
        position: None,
        following: axis(f, "the following axis")?,
        leading: leads(rest, None)?,
    })
}

/// `EGONSYNE(following, "FINE", position, "DCT", leading, position, num, den, ...)`:
/// every leading axis takes four arguments (axis, its synchronised position,
/// numerator, denominator), the hob first.
fn egonsyne(args: &[Arg<'_>]) -> Result<Op, String> {
    let [f, mode, pos, approach, rest @ ..] = args else {
        return Err(
            "EGONSYNE takes the following axis, \"FINE\", its position, \"DCT\", then each leading axis with its synchronised position, numerator and denominator"
                .into(),
        );
    };
    text(mode, "FINE")?;
    text(approach, "DCT")?;
    let Arg::Num(pos) = pos else {
        return Err("the following axis's synchronised position must be a number".into());
    };
    if rest.is_empty() || rest.len() % 4 != 0 {
        return Err(
            "each leading axis of EGONSYNE takes four arguments: axis, synchronised position, numerator, denominator"
                .into(),
        );
    }
    let mut leading = Vec::with_capacity(rest.len() / 4);
    for (i, q) in rest.chunks_exact(4).enumerate() {
        let Arg::Num(lead_pos) = q[1] else {
            return Err(format!(
                "the synchronised position of leading axis {} must be a number",
                i + 1
            ));
        };
        leading.push(triple(&[q[0], q[2], q[3]], i == 0, Some(lead_pos))?);
    }
    if leading.len() > 5 {
        return Err("a gearbox has one to five leading axes".into());
    }
    Ok(Op::GearOn {
        sync: true,
        position: Some(*pos),
        following: axis(f, "the following axis")?,
        leading,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(line: &str) -> Result<Op, String> {
        crate::one_block(line, body, block)
    }

    #[test]
    fn if_else_endif() {
        let Op::If(cond) = one("N150 IF R25>=R23*R24 ; EVERY POSITION HAS CUT").unwrap() else {
            panic!()
        };
        assert_eq!(cond.rel, expr::Rel::Ge);
        let mut r = [0.0; expr::PARAMS];
        (r[23], r[24], r[25]) = (4.0, 6.0, 23.0);
        assert!(!cond.eval(&r).unwrap());
        r[25] = 24.0;
        assert!(cond.eval(&r).unwrap());
        for (text, rel) in [
            ("IF R1==2", expr::Rel::Eq),
            ("IF R1<>2", expr::Rel::Ne),
            ("IF R1<2", expr::Rel::Lt),
            ("IF R1 <= 2", expr::Rel::Le),
            ("IF R1>2", expr::Rel::Gt),
        ] {
            let Op::If(c) = one(text).unwrap() else {
                panic!("{text}")
            };
            assert_eq!(c.rel, rel, "{text}");
        }
        assert_eq!(one("N160 ELSE").unwrap(), Op::Else);
        assert_eq!(one("N170 ENDIF").unwrap(), Op::EndIf);
        for bad in [
            "IF R1",
            "IF R1=2",
            "IF",
            "IFR1>2",
            "ENDIF R1=0",
            "IF R1>2 GOTOF L1",
        ] {
            assert!(one(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn egonsyne_y_group_with_three_arguments() {
        // The Y group of this block has no synchronised
        // position (axis, numerator, denominator); each leading axis of
        // EGONSYNE takes four arguments.
        let err = one("N260 EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Y,1.526579,1)").unwrap_err();
        assert!(err.contains("four arguments"), "{err}");
    }

    #[test]
    fn blocks_of_the_subset() {
        let Op::Motion(m) = one("N10 G0 G90 X=174.05 Z=82.0 A=2.3715").unwrap() else {
            panic!()
        };
        assert_eq!(m.interp, Some(Interp::Rapid));
        assert_eq!(m.words().len(), 3);
        assert!(m.words()[2].axis.is("A"));
        assert!(matches!(
            one("N20 M10 ; FIXTURE CLAMP").unwrap(),
            Op::MCode {
                code: 10,
                speed: None
            }
        ));
        let Op::MCode { speed: Some(s), .. } = one("N180 M3 S=358.099 ; HOB ON, RPM").unwrap()
        else {
            panic!()
        };
        assert_eq!(s.value, 358.099);
        assert!(matches!(
            one("N150 R26=TRUNC(R25/R23) ; SHIFT STEPS SO FAR").unwrap(),
            Op::Assign { param: 26, .. }
        ));
        let Op::GearOn {
            sync,
            leading,
            position,
            ..
        } = one("N260 EGONSYNE(C,\"FINE\",0,\"DCT\",B,0,1,25,Y,0,1.526579,1) ; SYNC").unwrap()
        else {
            panic!()
        };
        assert!(sync);
        assert_eq!(position.map(|p| p.value), Some(0.0));
        assert_eq!(leading.len(), 2);
        assert_eq!(leading[1].num.value, 1.526579);
        assert_eq!(leading[1].position.map(|p| p.value), Some(0.0));
        assert!(matches!(
            one("N215 G4 F=2.0 ; DWELL, S").unwrap(),
            Op::Dwell { .. }
        ));
        assert!(matches!(
            one("N290 MSG(\"CHANGE HOB TO HOB-M2-70\") ; HOB CHANGE").unwrap(),
            Op::Message
        ));
        let Op::Motion(m) = one("N150 CIP X=81.27 Z=50.0 I1=81.25 K1=70.0 F=19.099").unwrap()
        else {
            panic!()
        };
        assert_eq!(m.via.map(|v| v.0.value), Some(81.25));
        assert_eq!(body("; A COMMENT"), Ok(""));
    }

    #[test]
    fn lines_outside_the_subset_are_refused() {
        for bad in [
            "N10 G0 G90 X=12",               // no decimal point
            "N10 G00 X=1.0",                 // G00 is the FANUC spelling
            "N10 G0 G1 X=1.0",               // conflicting codes
            "N10 EGON(C,\"FINE\",B,1.0,25)", // the hob ratio is whole numbers
            "N10 EGON(C,\"FINE\",B,1,0)",    // zero denominator
            "N10 EGON(C,\"COARSE\",B,1,25)", // only FINE
            "N10 EGDEF(C,B,2)",              // coupling type
            "N10 M3 S=358",                  // speed without a point
            "N10 G4 X=1.0",                  // dwell with an axis
            "N10 X=1.0 X=2.0",               // repeated axis
            "N10 GOTOF LABEL",               // not in the subset
            "N10 R1000=1.0",                 // R0–R999
            "N10 CIP X=1.0 Z=2.0 F=1.0",     // no intermediate point
            "N10 G0 X=1.0 ; ÄÖ",             // not ASCII
            "N10",                           // number alone
        ] {
            assert!(one(bad).is_err(), "{bad} should be refused");
        }
    }
}
