//! A job's form, one per family, made from the documented example job
//! file of that family: every key the example writes (and every key it
//! shows commented out, as an optional field), in the example's order,
//! with the unit its name carries in the label and the example's comment as
//! the field's help. The form's values go back into a TOML job file that
//! `gearcam submit` would read, so the page and the CLI accept the same
//! jobs and refuse them with the same typed errors.

use gearcam_proto::{Code, JobError, Stage};

/// A form: its name, the example it is made from and its fields.
#[derive(Debug, Clone)]
pub(super) struct Form {
    /// The form's name in the page (`hobbing`, `spiral-face`, …).
    pub(super) name: &'static str,
    /// What the form is for.
    pub(super) title: &'static str,
    /// Every field, in the example's order.
    pub(super) fields: Vec<Field>,
}

/// What a field holds, from the example's literal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    /// A quoted string.
    Text,
    /// An integer.
    Int,
    /// A number.
    Float,
    /// `true` or `false`.
    Bool,
}

/// One key of the job file.
#[derive(Debug, Clone)]
pub(super) struct Field {
    /// The section, e.g. `gear`.
    pub(super) section: String,
    /// The key, e.g. `module_mm`.
    pub(super) key: String,
    /// The example's value (strings unquoted).
    pub(super) example: String,
    /// What the field holds.
    pub(super) kind: Kind,
    /// True when the example leaves it out (commented): empty means
    /// "not given" (the documented default or the knowledge base's proposal).
    pub(super) optional: bool,
    /// The example's comment.
    pub(super) help: String,
}

impl Field {
    /// The field's name in the form and in error reports: `section.key`.
    pub(super) fn name(&self) -> String {
        format!("{}.{}", self.section, self.key)
    }

    /// The label: the key without its unit, and the unit (`module (mm)`).
    pub(super) fn label(&self) -> String {
        let (stem, unit) = unit_of(&self.key);
        match unit {
            Some(u) => format!("{} ({u})", stem.replace('_', " ")),
            None => stem.replace('_', " "),
        }
    }
}

/// The unit a key's name ends in: `module_mm` → (`module`, `mm`).
pub(super) fn unit_of(key: &str) -> (&str, Option<&'static str>) {
    const UNITS: [(&str, &str); 9] = [
        ("_mm_per_rev", "mm/rev"),
        ("_mm_min", "mm/min"),
        ("_m_min", "m/min"),
        ("_mm", "mm"),
        ("_um", "µm"),
        ("_deg", "°"),
        ("_rpm", "rpm"),
        ("_min", "min"),
        ("_s", "s"),
    ];
    UNITS
        .iter()
        .find_map(|(suffix, unit)| key.strip_suffix(suffix).map(|stem| (stem, Some(*unit))))
        .unwrap_or((key, None))
}

/// The forms, each from its example.
pub(super) fn forms() -> Vec<Form> {
    [
        (
            "hobbing",
            "Gear hobbing (840D, FANUC EGB)",
            include_str!("../../../../examples/spur_840d.toml"),
        ),
        (
            "spiral-face",
            "Spiral face milling: a circular or annular face",
            include_str!("../../../../examples/face_annulus_fanuc.toml"),
        ),
        (
            "spiral-groove",
            "Spiral face milling: a planar spiral groove",
            include_str!("../../../../examples/groove_linuxcnc.toml"),
        ),
        (
            "wire-edm",
            "Spur-gear punch or die by wire EDM",
            include_str!("../../../../examples/die_m1z40_iso.toml"),
        ),
    ]
    .into_iter()
    .map(|(name, title, text)| Form {
        name,
        title,
        fields: fields_of(text),
    })
    .collect()
}

/// The form named `name`.
pub(super) fn form(name: &str) -> Option<Form> {
    forms().into_iter().find(|f| f.name == name)
}

/// The fields of a documented example job file: `key = value  # help`
/// lines (and commented-out `# key = value  # help` lines, optional) under
/// `[section]` headers; a comment line indented under a key continues its help.
pub(super) fn fields_of(text: &str) -> Vec<Field> {
    let mut fields: Vec<Field> = Vec::new();
    let mut section = String::new();
    for line in text.lines() {
        let trimmed = line.trim();
        if let Some(rest) = trimmed.strip_prefix('[') {
            if let Some((name, _)) = rest.split_once(']') {
                section = name.trim_matches(['[', ']']).to_string();
            }
            continue;
        }
        if section.is_empty() {
            continue;
        }
        let (optional, body) = match trimmed.strip_prefix('#') {
            Some(b) => (true, b.trim()),
            None => (false, trimmed),
        };
        match key_value(body) {
            Some((key, value, help)) => fields.push(Field {
                section: section.clone(),
                key: key.to_string(),
                kind: kind_of(value),
                example: value.trim_matches('"').to_string(),
                optional,
                help: help.to_string(),
            }),
            None if optional && line.starts_with(' ') => {
                if let Some(last) = fields.last_mut() {
                    last.help.push(' ');
                    last.help.push_str(body);
                }
            }
            None => {}
        }
    }
    fields
}

/// `key = value  # help` → its parts, when `key` is a bare TOML key.
fn key_value(body: &str) -> Option<(&str, &str, &str)> {
    let (key, rest) = body.split_once('=')?;
    let key = key.trim();
    if key.is_empty()
        || !key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return None;
    }
    let rest = rest.trim();
    let (value, help) = if let Some(stripped) = rest.strip_prefix('"') {
        let end = stripped.find('"')? + 2;
        let (v, h) = rest.split_at(end);
        (v, h.trim().trim_start_matches('#').trim())
    } else {
        match rest.split_once('#') {
            Some((v, h)) => (v.trim(), h.trim()),
            None => (rest, ""),
        }
    };
    (!value.is_empty()).then_some((key, value, help))
}

fn kind_of(literal: &str) -> Kind {
    if literal.starts_with('"') {
        Kind::Text
    } else if literal == "true" || literal == "false" {
        Kind::Bool
    } else if literal.contains(['.', 'e', 'E']) {
        Kind::Float
    } else {
        Kind::Int
    }
}

/// The job file of `values` (field name → text as typed) for `form`: every
/// non-empty field, typed as the form says. A value of the wrong type is a
/// typed error naming the field, the type expected and the text given.
pub(super) fn job_file(form: &Form, values: &[(String, String)]) -> Result<String, Vec<JobError>> {
    let value_of = |name: &str| {
        values
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.trim().to_string())
    };
    let mut errors = Vec::new();
    let mut text = String::new();
    let mut section = "";
    for f in &form.fields {
        let Some(v) = value_of(&f.name()).filter(|v| !v.is_empty()) else {
            continue;
        };
        let literal = match literal(f, &v) {
            Ok(l) => l,
            Err(e) => {
                errors.push(e);
                continue;
            }
        };
        if f.section != section {
            section = &f.section;
            text.push_str(&format!("\n[{section}]\n"));
        }
        text.push_str(&format!("{} = {literal}\n", f.key));
    }
    if errors.is_empty() {
        Ok(text)
    } else {
        Err(errors)
    }
}

/// `v` as a TOML literal of the field's kind.
fn literal(f: &Field, v: &str) -> Result<String, JobError> {
    let wrong = |expected: &str| {
        Stage::Station.error(
            Code::JOB_FILE_INVALID,
            &f.name(),
            expected,
            format!("{v:?}"),
            format!("{}: {expected}", f.label()),
        )
    };
    match f.kind {
        Kind::Text => Ok(toml::Value::String(v.to_string()).to_string()),
        Kind::Bool => match v {
            "true" | "false" => Ok(v.to_string()),
            _ => Err(wrong("true or false")),
        },
        Kind::Int => v
            .parse::<i64>()
            .map(|n| n.to_string())
            .map_err(|_| wrong("a whole number")),
        Kind::Float => v
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .map(|x| format!("{x:?}"))
            .ok_or_else(|| wrong("a number")),
    }
}

/// The form's values of a job file `text` (its keys, as text), and the
/// keys the form does not hold (e.g. `[[units]]` of a multi-unit job), so
/// an import that would lose them is refused rather than trimmed.
pub(super) fn values_of(form: &Form, text: &str) -> Result<Vec<(String, String)>, Vec<String>> {
    let table: toml::Table = match text.parse() {
        Ok(t) => t,
        Err(e) => return Err(vec![format!("not a TOML job file: {e}")]),
    };
    let mut values = Vec::new();
    let mut lost = Vec::new();
    for (section, content) in &table {
        let Some(keys) = content.as_table() else {
            lost.push(format!("[{section}]"));
            continue;
        };
        for (key, value) in keys {
            let name = format!("{section}.{key}");
            if !form.fields.iter().any(|f| f.name() == name) {
                lost.push(name);
                continue;
            }
            let shown = match value {
                toml::Value::String(s) => s.clone(),
                other => other.to_string(),
            };
            values.push((name, shown));
        }
    }
    if lost.is_empty() {
        Ok(values)
    } else {
        Err(lost)
    }
}

/// The form that holds a job file `text`: by its `[job] family` and, for
/// spiral face milling, whether it mills a `[face]` or a `[groove]`.
pub(super) fn form_for(text: &str) -> Option<Form> {
    let table: toml::Table = text.parse().ok()?;
    let family = table
        .get("job")
        .and_then(|j| j.get("family"))
        .and_then(|f| f.as_str())
        .unwrap_or("hobbing");
    let name = match family {
        "spiral-face" if table.contains_key("groove") => "spiral-groove",
        other => other,
    };
    form(name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hobbing_form_has_the_examples_keys_with_units_and_help() {
        let f = form("hobbing").unwrap();
        let module = f
            .fields
            .iter()
            .find(|x| x.name() == "gear.module_mm")
            .unwrap();
        assert_eq!(module.label(), "module (mm)");
        assert_eq!(module.kind, Kind::Float);
        assert!(!module.optional);
        assert_eq!(module.help, "normal module mn");
        let hand = f
            .fields
            .iter()
            .find(|x| x.name() == "gear.helix_hand")
            .unwrap();
        assert!(hand.optional, "a commented key is an optional field");
        assert_eq!(hand.kind, Kind::Text);
        let speed = f
            .fields
            .iter()
            .find(|x| x.name() == "process.cutting_speed_m_min")
            .unwrap();
        assert_eq!(speed.label(), "cutting speed (m/min)");
        let fixture = f
            .fields
            .iter()
            .find(|x| x.name() == "gear.fixture_height_mm")
            .unwrap();
        assert!(
            fixture.help.contains("clear of the table"),
            "{}",
            fixture.help
        );
    }

    #[test]
    fn every_form_reads_back_its_own_example_as_the_cli_does() {
        for f in forms() {
            let values: Vec<(String, String)> = f
                .fields
                .iter()
                .filter(|x| !x.optional)
                .map(|x| (x.name(), x.example.clone()))
                .collect();
            let text = job_file(&f, &values).unwrap();
            let spec = crate::jobfile::parse(&text, f.name)
                .unwrap_or_else(|e| panic!("{}: {e:?}\n{text}", f.name));
            let family = match f.name {
                "spiral-face" | "spiral-groove" => "spiral-face",
                other => other,
            };
            assert_eq!(spec.family().as_str(), family, "{}", f.name);
        }
    }

    #[test]
    fn a_value_of_the_wrong_type_names_the_field_and_what_it_takes() {
        let f = form("hobbing").unwrap();
        let errors = job_file(&f, &[("gear.teeth".into(), "twenty".into())]).unwrap_err();
        assert_eq!(errors[0].field, "gear.teeth");
        assert_eq!(errors[0].expected, "a whole number");
        assert_eq!(errors[0].got, "\"twenty\"");
    }

    #[test]
    fn an_import_that_the_form_cannot_hold_is_refused_naming_what_would_be_lost() {
        let f = form("hobbing").unwrap();
        let multi = "[job]\nmachine = \"H01\"\n[[units]]\nteeth = 20\n";
        assert_eq!(values_of(&f, multi).unwrap_err(), vec!["[units]"]);
        let ok = values_of(&f, "[gear]\nmodule_mm = 2.5\n").unwrap();
        assert_eq!(ok, vec![("gear.module_mm".to_string(), "2.5".to_string())]);
    }
}
