//! The journal's own tests: migrations of older journals, models kept.

use super::*;

/// The jobs table of the first journals, before any column was added.
const FIRST_JOBS_TABLE: &str = "CREATE TABLE jobs (
             seq INTEGER PRIMARY KEY AUTOINCREMENT, job TEXT NOT NULL UNIQUE,
             machine TEXT NOT NULL, part_number TEXT NOT NULL, request BLOB NOT NULL,
             request_sha256 TEXT NOT NULL, state TEXT NOT NULL,
             attempts INTEGER NOT NULL DEFAULT 0, accepted_at_ms INTEGER NOT NULL,
             updated_at_ms INTEGER NOT NULL, next_attempt_ms INTEGER NOT NULL,
             waiting_for TEXT, receipt_json TEXT, errors_json TEXT";

/// A journal written before the model's warnings were kept opens, gains
/// the column, and its jobs read with no warnings.
#[test]
fn a_journal_from_before_the_warnings_column_opens_and_reads() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("station.db");
    let conn = Connection::open(&path).unwrap();
    conn.execute_batch(&format!(
        "{FIRST_JOBS_TABLE});
         INSERT INTO jobs (job, machine, part_number, request, request_sha256, state,
                           accepted_at_ms, updated_at_ms, next_attempt_ms)
         VALUES ('OLD-1', 'H01', 'SP-1001', x'00', '-', 'accepted', 1, 1, 1);"
    ))
    .unwrap();
    drop(conn);
    let journal = Journal::open(&path).unwrap();
    let s = journal
        .status(&JobId::new("OLD-1").unwrap())
        .unwrap()
        .unwrap();
    assert_eq!(s.state, JobState::Accepted);
    assert!(s.warnings.is_empty());
    // It gained the models' table too: no model yet, then the one kept.
    let old = JobId::new("OLD-1").unwrap();
    assert_eq!(journal.model(&old).unwrap(), Some(None));
    assert!(journal.set_model(&old, b"model").unwrap());
    assert_eq!(journal.model(&old).unwrap(), Some(Some(b"model".to_vec())));
    // Opening again does not add the columns twice, and keeps the model.
    drop(journal);
    let journal = Journal::open(&path).unwrap();
    assert_eq!(journal.model(&old).unwrap(), Some(Some(b"model".to_vec())));
}

/// A journal that kept each model in its job's row opens with the
/// models in their own table, none lost, and the column gone (a state
/// change no longer rewrites the model).
#[test]
fn a_journal_with_models_in_the_jobs_rows_moves_them_to_their_own_table() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("station.db");
    let conn = Connection::open(&path).unwrap();
    conn.execute_batch(&format!(
        "{FIRST_JOBS_TABLE},
             warnings_json TEXT, model BLOB);
         INSERT INTO jobs (job, machine, part_number, request, request_sha256, state,
                           accepted_at_ms, updated_at_ms, next_attempt_ms, model)
         VALUES ('OLD-1', 'H01', 'SP-1001', x'00', '-', 'delivered', 1, 1, 1, x'0102'),
                ('OLD-2', 'H01', 'SP-1002', x'00', '-', 'accepted', 1, 1, 1, NULL);"
    ))
    .unwrap();
    drop(conn);
    let journal = Journal::open(&path).unwrap();
    let job = |id: &str| JobId::new(id).unwrap();
    assert_eq!(
        journal.model(&job("OLD-1")).unwrap(),
        Some(Some(vec![1, 2]))
    );
    assert_eq!(journal.model(&job("OLD-2")).unwrap(), Some(None));
    // The delivered job keeps its model; the running one gains one.
    assert!(!journal.set_model(&job("OLD-1"), b"late").unwrap());
    assert!(journal.set_model(&job("OLD-2"), b"new").unwrap());
    let columns: Vec<String> = journal
        .conn
        .prepare("SELECT name FROM pragma_table_info('jobs')")
        .unwrap()
        .query_map([], |r| r.get(0))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert!(!columns.iter().any(|c| c == "model"), "{columns:?}");
    drop(journal);
    let journal = Journal::open(&path).unwrap();
    assert_eq!(
        journal.model(&job("OLD-1")).unwrap(),
        Some(Some(vec![1, 2]))
    );
    assert_eq!(
        journal.model(&job("OLD-2")).unwrap(),
        Some(Some(b"new".to_vec()))
    );
}

/// A journal from before the quantity column gains it, filled from
/// each job's request; a new job's quantity is kept as submitted.
#[test]
fn every_job_says_its_quantity_an_old_journal_too() {
    let spec: gearcam_proto::JobSpec =
        toml::from_str(include_str!("../../../../examples/spur_840d.toml")).unwrap();
    let request = |id: &str, quantity: u32| {
        let mut spec = spec.clone();
        spec.job.quantity = quantity;
        JobRequest {
            job_id: JobId::new(id).unwrap(),
            submitted_at_ms: 1,
            submitted_by: "test".into(),
            spec,
        }
    };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("station.db");
    let conn = Connection::open(&path).unwrap();
    conn.execute_batch(&format!("{FIRST_JOBS_TABLE});"))
        .unwrap();
    conn.execute(
        "INSERT INTO jobs (job, machine, part_number, request, request_sha256, state,
                           accepted_at_ms, updated_at_ms, next_attempt_ms)
         VALUES ('OLD-7', 'H01', 'SP-1001', ?1, '-', 'delivered', 1, 1, 1)",
        [encode(&request("OLD-7", 7)).unwrap()],
    )
    .unwrap();
    drop(conn);
    let journal = Journal::open(&path).unwrap();
    let old = journal
        .status(&JobId::new("OLD-7").unwrap())
        .unwrap()
        .unwrap();
    assert_eq!(old.quantity, 7);
    let new = journal.submit(&request("NEW-12", 12), 5).unwrap();
    assert_eq!(new.quantity, 12);
    assert_eq!(
        journal
            .request_bytes(&JobId::new("NEW-12").unwrap())
            .unwrap(),
        Some(encode(&request("NEW-12", 12)).unwrap())
    );
}

/// A new journal holding job J-1 for H01 (the directory lives as long as
/// the first value).
fn journal_with_a_job() -> (tempfile::TempDir, Journal, JobId) {
    let dir = tempfile::tempdir().unwrap();
    let journal = Journal::open(&dir.path().join("station.db")).unwrap();
    let spec: gearcam_proto::JobSpec =
        serde_json::from_str(r#"{"job": {"machine": "H01", "part_number": "SP-1"}}"#).unwrap();
    let job = JobId::new("J-1").unwrap();
    let req = JobRequest {
        job_id: job.clone(),
        submitted_at_ms: 1,
        submitted_by: "planner".into(),
        spec,
    };
    journal.submit(&req, 1).unwrap();
    (dir, journal, job)
}

/// A model is kept while its job runs; once the job has ended, a model
/// arriving later does not replace the one it has; an unknown job has
/// no model and a job without one says so.
#[test]
fn an_ended_job_keeps_its_model() {
    let (_dir, journal, job) = journal_with_a_job();
    assert_eq!(journal.model(&job).unwrap(), Some(None));
    assert!(journal.set_model(&job, b"first").unwrap());
    assert!(journal.set_model(&job, b"again").unwrap());
    journal.cancel(&job, "planner", 2).unwrap();
    assert!(!journal.set_model(&job, b"late").unwrap());
    assert_eq!(journal.model(&job).unwrap(), Some(Some(b"again".to_vec())));
    let unknown = JobId::new("J-2").unwrap();
    assert_eq!(journal.model(&unknown).unwrap(), None);
    assert!(!journal.set_model(&unknown, b"x").unwrap());
}

/// The station asks for the due jobs ten times a second: the question is
/// answered from the partial index of unfinished jobs, never by a scan of
/// every job the journal holds.
#[test]
fn the_due_jobs_are_read_through_their_index() {
    let dir = tempfile::tempdir().unwrap();
    let journal = Journal::open(&dir.path().join("station.db")).unwrap();
    let plan: Vec<String> = journal
        .conn
        .prepare(&format!("EXPLAIN QUERY PLAN {DUE}"))
        .unwrap()
        .query_map(params![0i64, 1i64], |r| r.get::<_, String>(3))
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert!(
        plan.iter()
            .any(|step| step.contains("USING INDEX jobs_due")),
        "{plan:?}"
    );
    assert!(
        !plan.iter().any(|step| step.starts_with("SCAN")),
        "{plan:?}"
    );
}

/// The agents' questions are answered on a reader of their own: it sees a
/// job once its submission is committed, a cancellation as soon as it is,
/// and nothing of a group commit still open (the station's loop may be in
/// the middle of one while the reader answers).
#[test]
fn a_reader_sees_what_is_committed_and_only_that() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("station.db");
    let mut journal = Journal::open(&path).unwrap();
    let reader = JournalReader::open(&path).unwrap();
    let spec: gearcam_proto::JobSpec =
        serde_json::from_str(r#"{"job": {"machine": "H01", "part_number": "SP-1"}}"#).unwrap();
    let request = |job: &JobId| JobRequest {
        job_id: job.clone(),
        submitted_at_ms: 1,
        submitted_by: "planner".into(),
        spec: spec.clone(),
    };
    let first = JobId::new("J-1").unwrap();
    assert_eq!(reader.status(&first).unwrap(), None);
    journal.submit(&request(&first), 1).unwrap();
    let seen = reader.status(&first).unwrap().unwrap();
    assert_eq!(
        (seen.machine.as_str(), seen.state),
        ("H01", JobState::Accepted)
    );
    // A second job journaled in a group commit not yet committed is not
    // seen; the first stays readable meanwhile.
    let second = JobId::new("J-2").unwrap();
    journal
        .batch(Durability::Full, |j| {
            j.submit(&request(&second), 2).unwrap();
            assert_eq!(reader.status(&second).unwrap(), None);
            assert!(reader.status(&first).unwrap().is_some());
        })
        .unwrap();
    assert!(reader.status(&second).unwrap().is_some());
    journal.cancel(&first, "planner", 3).unwrap();
    assert_eq!(
        reader.status(&first).unwrap().unwrap().state,
        JobState::Cancelled
    );
}

/// The program's warnings (a predicted class worse than the drawing's) are
/// kept beside the model's, for status, each once however often the
/// program is produced.
#[test]
fn the_programs_warnings_join_the_models_once() {
    let (_dir, journal, job) = journal_with_a_job();
    let warning = |code, field: &str| Warning {
        code,
        field: field.into(),
        message: "look".into(),
    };
    let model = warning(
        gearcam_proto::Code::AXIAL_FEED_LIMIT,
        "process.feed_mm_per_rev",
    );
    let grade = warning(gearcam_proto::Code::PREDICTED_GRADE, "simulation.grade");
    let event = |stage, event| JobEvent {
        job_id: job.clone(),
        stage,
        at_ms: 2,
        event,
    };
    let modelled = event(
        Stage::Model,
        EventKind::Modelled {
            warnings: vec![model.clone()],
        },
    );
    assert!(journal.apply("model", &modelled, 2, 1000).unwrap());
    let programmed = event(
        Stage::Template,
        EventKind::Programmed {
            name: "SP_1".into(),
            sha256: "00".into(),
            predicted_grade: Some(9),
            warnings: vec![grade.clone()],
        },
    );
    for _ in 0..2 {
        journal.apply("template", &programmed, 3, 1000).unwrap();
    }
    let status = journal.status(&job).unwrap().unwrap();
    assert_eq!(status.warnings, vec![model, grade]);
}
