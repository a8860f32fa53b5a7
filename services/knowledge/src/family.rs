//! The one place the knowledge service tells the part families apart: each
//! family's planner ([`crate::plan`], [`crate::spiral`], [`crate::wire`])
//! plans a job of its family and records it; [`plan`] picks the planner by
//! the job's family.

use gearcam_proto::{encode, CodecError, FamilySpec, JobError, JobRequest};
use rusqlite::Connection;

use crate::cbr::CaseBase;

/// A job planned by its family's planner, ready to publish.
#[derive(Debug)]
pub(crate) struct Planned {
    /// The tool chosen: a hob, a mill or a wire.
    pub(crate) tool: String,
    /// The planner's confidence in the proposal, 0–1.
    pub(crate) confidence: f64,
    /// The family's plan message, encoded.
    pub(crate) payload: Result<Vec<u8>, CodecError>,
}

/// Plans `req` with its family's planner and records the planned job in the
/// jobs library (a failure to record is logged: the plan still goes out).
pub(crate) fn plan(
    conn: &Connection,
    cases: &CaseBase,
    req: &JobRequest,
) -> Result<Planned, Vec<JobError>> {
    let recorded = |job: &gearcam_proto::JobId, r: Result<(), crate::KnowledgeError>| {
        if let Err(e) = r {
            tracing::warn!(%job, error = %e, "cannot record the planned job");
        }
    };
    Ok(match &req.spec.part {
        FamilySpec::Hobbing(_) => {
            let plan = crate::plan::plan_with(conn, cases, req)?;
            recorded(
                &plan.job_id,
                crate::learn::record_planned(conn, &plan, gearcam_proto::now_ms()),
            );
            Planned {
                tool: plan.hob.id.clone(),
                confidence: plan.confidence,
                payload: encode(&plan),
            }
        }
        FamilySpec::SpiralFace(_) => {
            let plan = crate::spiral::plan_spiral(conn, req)?;
            recorded(
                &plan.job_id,
                crate::spiral::record_planned(conn, &plan, gearcam_proto::now_ms()),
            );
            Planned {
                tool: plan.tool.id.clone(),
                confidence: plan.confidence,
                payload: encode(&plan),
            }
        }
        FamilySpec::WireEdm(_) => {
            let plan = crate::wire::plan_wire(conn, req)?;
            recorded(
                &plan.job_id,
                crate::wire::record_planned(conn, &plan, gearcam_proto::now_ms()),
            );
            Planned {
                tool: plan.process.wire.clone(),
                confidence: plan.confidence,
                payload: encode(&plan),
            }
        }
    })
}
