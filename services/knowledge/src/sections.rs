//! A family's sections of a job, for that family's planner.

use gearcam_proto::{Code, Family, JobError, JobRequest, JobSpec, Stage};

/// The sections of `family` in `req`'s job (`get` is [`JobSpec::hobbing`],
/// [`JobSpec::spiral`] or [`JobSpec::wire`]), or `SECTION_FAMILY` when a
/// family's planner is handed a job of another family.
pub(crate) fn sections<T>(
    req: &JobRequest,
    family: Family,
    get: fn(&JobSpec) -> Option<&T>,
) -> Result<&T, JobError> {
    get(&req.spec).ok_or_else(|| {
        Stage::Knowledge.error(
            Code::SECTION_FAMILY,
            "job.family",
            family.as_str(),
            req.spec.family().as_str(),
            format!(
                "the {} planner plans {} jobs only",
                family.as_str(),
                family.as_str()
            ),
        )
    })
}
