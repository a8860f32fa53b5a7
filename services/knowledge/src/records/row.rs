//! Reading one row of a library's table into its typed record: every
//! error names the library, the record's key and the field.

use rusqlite::types::{FromSql, Type, ValueRef};
use rusqlite::{Connection, Row};

use crate::library::{Check, Library};
use crate::KnowledgeError;

/// A library's typed record, read from one row of its table.
pub(super) trait TableRecord: Sized {
    /// The library: its table, key and fields.
    const LIBRARY: &'static Library;

    /// Reads every field of the record from its row.
    fn from_row(row: &RecordRow<'_, '_>) -> Result<Self, KnowledgeError>;
}

/// One row of a library's table as it is read: every error names the
/// library, the record's key and the field.
pub(super) struct RecordRow<'a, 'r> {
    lib: &'static Library,
    row: &'a Row<'r>,
    id: String,
}

impl<'a, 'r> RecordRow<'a, 'r> {
    pub(super) fn new(lib: &'static Library, row: &'a Row<'r>) -> RecordRow<'a, 'r> {
        let id = match row.get_ref(lib.key) {
            Ok(ValueRef::Text(t)) => String::from_utf8_lossy(t).into_owned(),
            Ok(ValueRef::Integer(i)) => i.to_string(),
            Ok(ValueRef::Real(x)) => x.to_string(),
            Ok(ValueRef::Null) | Ok(ValueRef::Blob(_)) | Err(_) => "(no key)".to_string(),
        };
        RecordRow { lib, row, id }
    }

    /// A field's value as the type `T` (`Option<T>` for a field that may be NULL).
    pub(super) fn get<T: FromSql>(&self, field: &'static str) -> Result<T, KnowledgeError> {
        self.row
            .get(field)
            .map_err(|e| self.error(field, describe(&e)))
    }

    /// A text field that is one of the field's choices, read by `parse`.
    pub(super) fn choice<T>(
        &self,
        field: &'static str,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<T, KnowledgeError> {
        let text: String = self.get(field)?;
        parse(&text).ok_or_else(|| self.not_a_choice(field, &text))
    }

    /// A text field that may be NULL and else is one of the field's choices.
    pub(super) fn choice_or_null<T>(
        &self,
        field: &'static str,
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Option<T>, KnowledgeError> {
        let text: Option<String> = self.get(field)?;
        text.map(|t| parse(&t).ok_or_else(|| self.not_a_choice(field, &t)))
            .transpose()
    }

    /// The record's key as read (`(no key)` when it is NULL).
    pub(super) fn id(&self) -> &str {
        &self.id
    }

    fn not_a_choice(&self, field: &'static str, text: &str) -> KnowledgeError {
        let allowed = self
            .lib
            .fields
            .iter()
            .find(|f| f.name == field)
            .and_then(|f| match f.check {
                Check::OneOf(v) => Some(v.join(", ")),
                _ => None,
            });
        self.error(
            field,
            match allowed {
                Some(v) => format!("{text:?} is not one of {v}"),
                None => format!("{text:?} is not a value of this field"),
            },
        )
    }

    fn error(&self, field: &str, detail: String) -> KnowledgeError {
        record_error(self.lib, &self.id, field, detail)
    }
}

pub(super) fn record_error(lib: &Library, id: &str, field: &str, detail: String) -> KnowledgeError {
    KnowledgeError::Record {
        library: lib.name,
        id: id.to_string(),
        field: field.to_string(),
        detail,
    }
}

/// What is wrong with a column's value, in words.
pub(super) fn describe(e: &rusqlite::Error) -> String {
    match e {
        rusqlite::Error::InvalidColumnType(_, _, Type::Null) => {
            "missing: NULL in a required field".to_string()
        }
        rusqlite::Error::InvalidColumnType(_, _, t) => {
            format!("unreadable: a value stored as {t}, not of the field's type")
        }
        rusqlite::Error::IntegralValueOutOfRange(_, v) => {
            format!("unreadable: {v} is out of the field's range")
        }
        rusqlite::Error::InvalidColumnName(_) => "no such column in the table".to_string(),
        other => format!("unreadable: {other}"),
    }
}

/// Every record of a flat library, ordered by key.
pub(super) fn read_all<T: TableRecord>(conn: &Connection) -> Result<Vec<T>, KnowledgeError> {
    let lib = T::LIBRARY;
    let sql = format!(
        "SELECT {} FROM {} ORDER BY {}",
        lib.columns(),
        lib.table,
        lib.key
    );
    let mut stmt = conn.prepare_cached(&sql)?;
    let mut rows = stmt.query([])?;
    let mut out = Vec::new();
    while let Some(row) = rows.next()? {
        out.push(T::from_row(&RecordRow::new(lib, row))?);
    }
    Ok(out)
}

/// One record of a flat library by key (the table's own comparison: a
/// material's name ignores case).
pub(super) fn read_one<T: TableRecord>(
    conn: &Connection,
    key: &str,
) -> Result<Option<T>, KnowledgeError> {
    let lib = T::LIBRARY;
    let sql = format!(
        "SELECT {} FROM {} WHERE {} = ?1",
        lib.columns(),
        lib.table,
        lib.key
    );
    let mut stmt = conn.prepare_cached(&sql)?;
    let mut rows = stmt.query([key])?;
    match rows.next()? {
        Some(row) => Ok(Some(T::from_row(&RecordRow::new(lib, row))?)),
        None => Ok(None),
    }
}
