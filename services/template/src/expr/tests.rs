use super::*;

fn run(text: &str, names: &[(&str, TplValue)]) -> Result<TplValue, String> {
    let mut resolve = |n: &str| names.iter().position(|(k, _)| *k == n);
    let e = compile(text, &mut resolve).map_err(|e| e.to_string())?;
    let vars: Vec<TplValue> = names.iter().map(|(_, v)| v.clone()).collect();
    e.eval(&vars, &mut EvalState::new(1000))
        .map_err(|e| e.to_string())
}

#[test]
fn arithmetic_comparison_and_logic() {
    let p = [("X1", TplValue::Num(74.05)), ("f1", TplValue::Num(100.0))];
    assert_eq!(run("X1 + f1", &p), Ok(TplValue::Num(174.05)));
    assert_eq!(run("2 + 3 * 4 - -1", &p), Ok(TplValue::Num(15.0)));
    assert_eq!(run("(2 + 3) * 4 / 5 % 3", &p), Ok(TplValue::Num(1.0)));
    assert_eq!(
        run("X1 > 70 and not (f1 == 3)", &p),
        Ok(TplValue::Bool(true))
    );
    assert_eq!(run("false or 1 <= 0", &p), Ok(TplValue::Bool(false)));
    // Short-circuit: the right side would be a type error.
    assert_eq!(run("false and 1", &p), Ok(TplValue::Bool(false)));
}

#[test]
fn strings_and_nc_formatting() {
    let p = [("X", TplValue::Num(74.05)), ("Z", TplValue::Num(-0.00001))];
    // docs/programs.md#standard-templates: "G90 X" + X + " Z" + Z, with the numbers written as NC numbers.
    assert_eq!(
        run("\"G90 X\" + nc(X) + \" Z\" + nc(Z)", &p),
        Ok(TplValue::from("G90 X74.05 Z0.0"))
    );
    assert_eq!(run("deg(2.37154321)", &p), Ok(TplValue::from("2.3715")));
    assert_eq!(run("factor(1.5265789)", &p), Ok(TplValue::from("1.526579")));
    assert!(run("\"X\" + X", &p).unwrap_err().contains("nc()"));
}

#[test]
fn functions() {
    let p = [("m.x", TplValue::Null), ("s", TplValue::from("a(b);c"))];
    assert_eq!(run("has(m.x)", &p), Ok(TplValue::Bool(false)));
    assert_eq!(
        run("if(has(m.x), nc(m.x), \"\")", &p),
        Ok(TplValue::from(""))
    );
    assert_eq!(run("upper(\"right\")", &p), Ok(TplValue::from("RIGHT")));
    assert_eq!(
        run("\"R26*\" + text(2) + text(s)", &p),
        Ok(TplValue::from("R26*2a(b);c"))
    );
    assert!(run("text(2.5)", &p).is_err());
    assert_eq!(run("int(2.6) + trunc(2.6)", &p), Ok(TplValue::Num(5.0)));
    assert_eq!(run("round(sin(30) * 1000)", &p), Ok(TplValue::Num(500.0)));
    assert_eq!(run("max(1, 2) + min(1, 2)", &p), Ok(TplValue::Num(3.0)));
}

#[test]
fn compile_errors_name_the_column() {
    let e = run("1 +", &[]).unwrap_err();
    assert!(e.contains("column 4") && e.contains("a value"), "{e}");
    let e = run("nope + 1", &[]).unwrap_err();
    assert!(e.contains("known parameter"), "{e}");
    let e = run("exec(1)", &[]).unwrap_err();
    assert!(e.contains("known function"), "{e}");
    let e = run("nc(1, 2)", &[]).unwrap_err();
    assert!(e.contains("1 argument"), "{e}");
    let e = run("(1", &[]).unwrap_err();
    assert!(e.contains("`)`"), "{e}");
}

#[test]
fn evaluation_is_bounded() {
    let mut resolve = |_: &str| None;
    let e = compile("1 + 1 + 1 + 1", &mut resolve).unwrap();
    let err = e.eval(&[], &mut EvalState::new(3)).unwrap_err();
    assert_eq!(err, EvalError::Budget(3));
}

#[test]
fn output_writes_integers_and_refuses_fractions() {
    let mut s = String::new();
    write_output(&mut s, &TplValue::Num(25.0)).unwrap();
    write_output(&mut s, &TplValue::from(" X")).unwrap();
    assert_eq!(s, "25 X");
    assert!(write_output(&mut s, &TplValue::Num(0.1)).is_err());
    assert!(write_output(&mut s, &TplValue::Null).is_err());
}
