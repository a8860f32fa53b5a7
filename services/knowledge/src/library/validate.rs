//! Validation of a record before it is written: field by field, the
//! library's cross-field rules, and whole machine profiles.

use gearcam_proto::Code;
use gearcam_proto::{JobError, MachineProfile, Stage};
use serde_json::Value;

use super::defs::MACHINES;
use super::fields::Check::{Id, OneOf, Positive, Range};
use super::fields::Kind::{Bool, Int, Real, Text};
use super::fields::{expected_of, Def, Field, Library, Need, Outcome, Record};

fn is_id(s: &str) -> bool {
    !s.is_empty()
        && s.len() <= 64
        && s.chars().next().is_some_and(|c| c.is_ascii_alphanumeric())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}

pub(super) fn show(v: &Value) -> String {
    match v {
        Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

/// Checks one field's value; returns the normalised value (NULL for an absent optional).
fn check_field(field: &Field, v: Option<&Value>, errors: &mut Vec<JobError>) -> Value {
    let v = match v {
        None | Some(Value::Null) => match field.need {
            Need::Required => {
                errors.push(Stage::Knowledge.error(
                    Code::FIELD_MISSING,
                    field.name,
                    expected_of(field),
                    "nothing",
                    format!("{} is required ({})", field.name, field.doc),
                ));
                return Value::Null;
            }
            Need::Optional => return Value::Null,
            Need::Default(d) => match d {
                Def::Real(x) => Value::from(x),
                Def::Int(x) => Value::from(x),
                Def::Text(s) => Value::from(s),
                Def::Bool(b) => Value::from(b),
            },
        },
        Some(v) => v.clone(),
    };
    let bad = |errors: &mut Vec<JobError>| {
        errors.push(Stage::Knowledge.error(
            Code::FIELD_INVALID,
            field.name,
            expected_of(field),
            show(&v),
            format!("{}: {}", field.name, field.doc),
        ));
        Value::Null
    };
    let num = match (field.kind, &v) {
        (Real, Value::Number(n)) => n.as_f64(),
        (Int, Value::Number(n)) => n
            .as_i64()
            .map(|i| i as f64)
            .or_else(|| n.as_f64().filter(|x| x.fract() == 0.0)),
        (Bool, Value::Bool(_)) | (Text, Value::String(_)) => None,
        _ => return bad(errors),
    };
    if let Some(x) = num {
        let ok = x.is_finite()
            && match field.check {
                Range(lo, hi) => (lo..=hi).contains(&x),
                Positive => x > 0.0,
                _ => true,
            };
        if !ok {
            return bad(errors);
        }
        return if field.kind == Int {
            Value::from(x as i64)
        } else {
            Value::from(x)
        };
    }
    if let Value::String(s) = &v {
        let ok = match field.check {
            OneOf(allowed) => allowed.contains(&s.as_str()),
            Id => is_id(s),
            _ => true,
        };
        if !ok {
            return bad(errors);
        }
    }
    v
}

/// Validates a whole record of a flat library: unknown fields, missing
/// required fields, types and ranges, and the library's cross-field rules.
/// Returns the normalised record with every field present (NULL for absent
/// optional ones).
pub fn validate(lib: &Library, rec: &Record) -> Outcome<Record> {
    if lib.name == MACHINES.name {
        return validate_machine(rec).map(|(_, r)| r);
    }
    let mut errors = Vec::new();
    for k in rec.keys() {
        if !lib.fields.iter().any(|f| f.name == k) {
            errors.push(Stage::Knowledge.error(
                Code::UNKNOWN_FIELD,
                k,
                format!(
                    "one of {}",
                    lib.fields
                        .iter()
                        .map(|f| f.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                k.as_str(),
                format!("{} records have no field {k:?}", lib.name),
            ));
        }
    }
    let mut out = Record::new();
    for field in lib.fields {
        let v = check_field(field, rec.get(field.name), &mut errors);
        out.insert(field.name.to_string(), v);
    }
    cross_checks(lib, &out, &mut errors);
    if errors.is_empty() {
        Ok(out)
    } else {
        Err(errors)
    }
}

fn num(r: &Record, k: &str) -> Option<f64> {
    r.get(k).and_then(Value::as_f64)
}

fn cross_checks(lib: &Library, r: &Record, errors: &mut Vec<JobError>) {
    match lib.name {
        "hobs" => {
            if let (Some(u), Some(l)) = (num(r, "usable_length_mm"), num(r, "length_mm")) {
                if u > l {
                    errors.push(Stage::Knowledge.error(
                        Code::FIELD_INVALID,
                        "usable_length_mm",
                        format!("≤ length_mm = {l}"),
                        u.to_string(),
                        "the usable length cannot exceed the hob's length",
                    ));
                }
                if let Some(s) = num(r, "shift_position_mm") {
                    if s > u {
                        errors.push(Stage::Knowledge.error(
                            Code::FIELD_INVALID,
                            "shift_position_mm",
                            format!("≤ usable_length_mm = {u}"),
                            s.to_string(),
                            "the shift position lies inside the usable length",
                        ));
                    }
                }
            }
        }
        "workpieces" => {
            let beta = num(r, "helix_angle_deg").unwrap_or(0.0);
            if beta != 0.0 && r.get("helix_hand").is_none_or(Value::is_null) {
                errors.push(Stage::Knowledge.error(
                    Code::FIELD_MISSING,
                    "helix_hand",
                    "right or left (the helix angle is not zero)",
                    "nothing",
                    "a helical gear needs the hand of its helix",
                ));
            }
        }
        _ => {}
    }
}

fn validate_machine(rec: &Record) -> Outcome<(MachineProfile, Record)> {
    let mut rec = rec.clone();
    let source = match rec.remove("source") {
        None | Some(Value::Null) => "user".to_string(),
        Some(Value::String(s)) => s,
        Some(other) => {
            return Err(vec![Stage::Knowledge.error(
                Code::FIELD_INVALID,
                "source",
                "a string",
                show(&other),
                "source says where the machine data comes from",
            )])
        }
    };
    let value = Value::Object(rec);
    let profile: MachineProfile = serde_path_to_error::deserialize(&value).map_err(|e| {
        vec![Stage::Knowledge.error(
            Code::FIELD_INVALID,
            &e.path().to_string(),
            "a complete machine profile (see `gearcam kb show machines H01` for one)",
            e.inner().to_string(),
            format!("machine profile field {}: {}", e.path(), e.inner()),
        )]
    })?;
    let mut errors = Vec::new();
    let l = &profile.limits;
    for (name, [lo, hi]) in [
        ("limits.module_mm", l.module_mm),
        ("limits.x_mm", l.x_mm),
        ("limits.z_mm", l.z_mm),
    ] {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            errors.push(Stage::Knowledge.error(
                Code::FIELD_INVALID,
                name,
                "[min, max] with min < max",
                format!("[{lo}, {hi}]"),
                "a range's lower end must lie below its upper end",
            ));
        }
    }
    for (name, v) in [
        ("limits.max_workpiece_od_mm", l.max_workpiece_od_mm),
        ("limits.max_hob_od_mm", l.max_hob_od_mm),
        ("limits.max_hob_rpm", l.max_hob_rpm),
        ("limits.max_table_rpm", l.max_table_rpm),
        ("limits.max_axial_feed_mm_min", l.max_axial_feed_mm_min),
        ("limits.max_swivel_deg", l.max_swivel_deg),
    ] {
        if !(v.is_finite() && v > 0.0) {
            errors.push(Stage::Knowledge.error(
                Code::FIELD_INVALID,
                name,
                "a number > 0",
                v.to_string(),
                "machine limits are positive",
            ));
        }
    }
    let s = profile.settings.swivel_sign;
    if s != 1.0 && s != -1.0 {
        errors.push(Stage::Knowledge.error(
            Code::FIELD_INVALID,
            "settings.swivel_sign",
            "1 or -1",
            s.to_string(),
            "the swivel axis sign: A = swivel_sign·η + swivel_offset_deg (docs/hobbing.md)",
        ));
    }
    for (name, axis) in [
        ("axes.radial", &profile.axes.radial),
        ("axes.axial", &profile.axes.axial),
        ("axes.swivel", &profile.axes.swivel),
        ("axes.hob", &profile.axes.hob),
        ("axes.table", &profile.axes.table),
        ("axes.shift", &profile.axes.shift),
    ] {
        if axis.is_empty()
            || axis.len() > 8
            || !axis.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            errors.push(Stage::Knowledge.error(
                Code::FIELD_INVALID,
                name,
                "an axis name of 1–8 letters, digits or _",
                format!("{axis:?}"),
                "axis names are written into NC programs",
            ));
        }
    }
    if !errors.is_empty() {
        return Err(errors);
    }
    let mut out = match serde_json::to_value(&profile) {
        Ok(Value::Object(m)) => m,
        _ => Record::new(),
    };
    out.insert("source".into(), Value::from(source));
    Ok((profile, out))
}
