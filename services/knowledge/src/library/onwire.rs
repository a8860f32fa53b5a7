//! Records as the bus carries them ([`KbRecord`]: MessagePack values) and
//! back: the library's records are JSON objects, the wire's are
//! [`KbValue`]s.

use gearcam_proto::plan::{KbRecord, KbValue};
use serde_json::Value;

use super::fields::Record;

/// A wire record as a JSON record.
pub fn record_from_wire(r: &KbRecord) -> Record {
    r.iter()
        .map(|(k, v)| (k.clone(), value_from_wire(v)))
        .collect()
}

fn value_from_wire(v: &KbValue) -> Value {
    match v {
        KbValue::Null => Value::Null,
        KbValue::Bool(b) => Value::from(*b),
        KbValue::Int(i) => Value::from(*i),
        KbValue::Float(x) => Value::from(*x),
        KbValue::Text(s) => Value::from(s.as_str()),
        KbValue::List(l) => Value::Array(l.iter().map(value_from_wire).collect()),
        KbValue::Map(m) => Value::Object(record_from_wire(m)),
    }
}

/// A JSON record as a wire record.
pub fn record_to_wire(r: &Record) -> KbRecord {
    r.iter()
        .map(|(k, v)| (k.clone(), value_to_wire(v)))
        .collect()
}

fn value_to_wire(v: &Value) -> KbValue {
    match v {
        Value::Null => KbValue::Null,
        Value::Bool(b) => KbValue::Bool(*b),
        Value::Number(n) => n
            .as_i64()
            .map(KbValue::Int)
            .unwrap_or_else(|| KbValue::Float(n.as_f64().unwrap_or(f64::NAN))),
        Value::String(s) => KbValue::Text(s.clone()),
        Value::Array(a) => KbValue::List(a.iter().map(value_to_wire).collect()),
        Value::Object(m) => KbValue::Map(record_to_wire(m)),
    }
}
