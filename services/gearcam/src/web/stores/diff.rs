//! The line diff of two versions of a program (the `similar` crate's
//! Myers diff), shown as a table: removed lines marked `-`, added lines
//! `+`, three lines of context around each change; every line is text.

use axum::extract::{Path, Query, State};
use axum::http::StatusCode;
use axum::response::IntoResponse;
use axum::Extension;
use maud::{html, Markup};
use serde::Deserialize;
use similar::{ChangeTag, TextDiff};

use super::{
    answered, bad_input, machine_of, on_the_bus, program_href, program_name_of, seq_of, style,
    Reply,
};
use crate::store;
use crate::web::auth::Session;
use crate::web::{page, Web};

/// Unchanged lines shown around each change.
const CONTEXT_LINES: usize = 3;

/// One row of a diff table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) enum Row {
    /// Unchanged lines left out between two changes.
    Gap,
    /// A line: removed (`Delete`), added (`Insert`) or unchanged, with its
    /// line numbers (from 1) in the old and the new text.
    Line {
        /// What happened to it.
        tag: ChangeTag,
        /// Its number in the old text.
        old: Option<usize>,
        /// Its number in the new text.
        new: Option<usize>,
        /// The line without its line end.
        text: String,
    },
}

/// The rows of the diff from `old` to `new`, and the lines removed and
/// added; no row when the texts are the same.
pub(super) fn diff_rows(old: &str, new: &str) -> (Vec<Row>, usize, usize) {
    let diff = TextDiff::from_lines(old, new);
    let (mut rows, mut removed, mut added) = (Vec::new(), 0, 0);
    for (i, group) in diff.grouped_ops(CONTEXT_LINES).iter().enumerate() {
        if i > 0 {
            rows.push(Row::Gap);
        }
        for op in group {
            for change in diff.iter_changes(op) {
                match change.tag() {
                    ChangeTag::Delete => removed += 1,
                    ChangeTag::Insert => added += 1,
                    ChangeTag::Equal => {}
                }
                rows.push(Row::Line {
                    tag: change.tag(),
                    old: change.old_index().map(|n| n + 1),
                    new: change.new_index().map(|n| n + 1),
                    text: change.value().trim_end_matches(['\n', '\r']).to_string(),
                });
            }
        }
    }
    (rows, removed, added)
}

/// The diff from `old` (version `a`) to `new` (version `b`) as a table.
pub(super) fn diff_table(a: u64, old: &str, b: u64, new: &str) -> Markup {
    let (rows, removed, added) = diff_rows(old, new);
    html! {
        @if rows.is_empty() {
            p #same { "Versions " (a) " and " (b) " have the same text." }
        } @else {
            p #summary { (removed) " line(s) removed, " (added) " line(s) added from version " (a) " to version " (b) }
            table.diff #diff {
                thead { tr { th { (a) } th { (b) } th { "" } th { "line" } } }
                tbody {
                    @for row in &rows {
                        @match row {
                            Row::Gap => tr.hunk { td { "…" } td { "…" } td {} td { "unchanged lines" } },
                            Row::Line { tag, old, new, text } => {
                                @let (class, mark) = match tag {
                                    ChangeTag::Delete => ("del", "-"),
                                    ChangeTag::Insert => ("add", "+"),
                                    ChangeTag::Equal => ("same", " "),
                                };
                                tr class=(class) {
                                    td.n { @if let Some(n) = old { (n) } }
                                    td.n { @if let Some(n) = new { (n) } }
                                    td.mark { (mark) }
                                    td { (text) }
                                }
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The query of a diff: the two versions.
#[derive(Debug, Default, Deserialize)]
pub(super) struct Versions {
    /// The old version.
    #[serde(default)]
    a: Option<String>,
    /// The new version.
    #[serde(default)]
    b: Option<String>,
}

/// `GET /machines/{machine}/programs/{name}/diff?a=SEQ&b=SEQ`: what
/// changed from version `a` to version `b`.
pub(super) async fn diff_page(
    State(web): State<Web>,
    Extension(session): Extension<Session>,
    Path((machine, name)): Path<(String, String)>,
    Query(q): Query<Versions>,
) -> Reply {
    let machine = machine_of(&session, &machine)?;
    let name = program_name_of(&session, &name)?;
    let mut seqs = [0u64; 2];
    for (slot, (field, given)) in seqs.iter_mut().zip([("a", &q.a), ("b", &q.b)]) {
        let Some(given) = given else {
            return Err(bad_input(
                &session,
                StatusCode::BAD_REQUEST,
                field,
                "a version number from the program's history, e.g. 3",
                "nothing",
            ));
        };
        *slot = seq_of(&session, field, given)?;
    }
    let [a, b] = seqs;
    on_the_bus(&web, &session, &machine).await?;
    let what = format!("{name} at {machine}: version {a} → version {b}");
    let old = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, a).await,
    )?;
    let new = answered(
        &session,
        &what,
        store::version(&web.bus, &machine, name, b).await,
    )?;
    let href = program_href(&machine, name);
    let body = html! {
        p { a href=(href) { "← " (name) " at " (machine) } }
        h1 { (what) }
        (style())
        p.muted {
            a href=(format!("{href}/versions/{a}")) { "version " (a) } ": " (old.version.state) " " (gearcam_proto::utc_text(old.version.stored_at_ms)) ", job " (old.version.job)
            " · "
            a href=(format!("{href}/versions/{b}")) { "version " (b) } ": " (new.version.state) " " (gearcam_proto::utc_text(new.version.stored_at_ms)) ", job " (new.version.job)
        }
        (diff_table(a, &old.text, b, &new.text))
    };
    Ok((StatusCode::OK, page(&what, Some(&session), body)).into_response())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_line_is_removed_and_added_with_its_numbers() {
        let old = "%\nN10 G0\nN20 X1\nN30 M2\n";
        let new = "%\nN10 G0\nN20 X2\nN30 M2\n";
        let (rows, removed, added) = diff_rows(old, new);
        assert_eq!((removed, added), (1, 1));
        let changed: Vec<_> = rows
            .iter()
            .filter_map(|r| match r {
                Row::Line {
                    tag,
                    old,
                    new,
                    text,
                } if *tag != ChangeTag::Equal => Some((*tag, *old, *new, text.as_str())),
                _ => None,
            })
            .collect();
        assert_eq!(
            changed,
            vec![
                (ChangeTag::Delete, Some(3), None, "N20 X1"),
                (ChangeTag::Insert, None, Some(3), "N20 X2"),
            ]
        );
        assert_eq!(diff_rows(old, old).0, Vec::new());
    }

    #[test]
    fn far_apart_changes_are_two_hunks() {
        let old: String = (1..=20).map(|i| format!("L{i}\n")).collect();
        let new = old.replace("L2\n", "L2x\n").replace("L19\n", "L19x\n");
        let (rows, ..) = diff_rows(&old, &new);
        assert_eq!(rows.iter().filter(|r| **r == Row::Gap).count(), 1);
    }

    #[test]
    fn a_line_of_markup_is_shown_as_text() {
        let html = diff_table(1, "a\n", 2, "<script>alert(1)</script>\n").into_string();
        assert!(
            html.contains("&lt;script&gt;alert(1)&lt;/script&gt;"),
            "{html}"
        );
        assert!(!html.contains("<script>"), "{html}");
    }
}
