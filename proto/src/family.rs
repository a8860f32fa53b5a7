//! The plan and the model of any family, as the model service, the
//! template service and the agents receive them: one envelope kind per
//! family, told apart when decoded.

use crate::codec::{decode, kind_of, Incoming, Message};
use crate::error::CodecError;
use crate::ids::{JobId, MachineId};
use crate::job::Family;
use crate::model::MachiningModel;
use crate::plan::ProcessPlan;
use crate::spiral::{SpiralModel, SpiralPlan};
use crate::wire::{WireModel, WirePlan};

/// A plan of any family, as the model service receives it.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyPlan {
    /// Hobbing.
    Hobbing(Box<ProcessPlan>),
    /// Spiral face milling.
    Spiral(Box<SpiralPlan>),
    /// Wire EDM.
    Wire(Box<WirePlan>),
}

impl AnyPlan {
    /// The job's id.
    pub fn job_id(&self) -> &JobId {
        match self {
            AnyPlan::Hobbing(p) => &p.job_id,
            AnyPlan::Spiral(p) => &p.job_id,
            AnyPlan::Wire(p) => &p.job_id,
        }
    }
}

impl Incoming for AnyPlan {
    const KINDS: &'static str = "process_plan, spiral_plan or wire_plan";
    fn decode_incoming(bytes: &[u8]) -> Result<Self, CodecError> {
        match kind_of(bytes, Self::KINDS)?.as_str() {
            WirePlan::KIND => {
                let p: WirePlan = decode(bytes)?;
                let job = p.request.spec.family();
                of_family(
                    WirePlan::KIND,
                    Family::WireEdm,
                    AnyPlan::Wire(Box::new(p)),
                    job,
                )
            }
            SpiralPlan::KIND => {
                let p: SpiralPlan = decode(bytes)?;
                let job = p.request.spec.family();
                of_family(
                    SpiralPlan::KIND,
                    Family::SpiralFace,
                    AnyPlan::Spiral(Box::new(p)),
                    job,
                )
            }
            ProcessPlan::KIND => {
                let p: ProcessPlan = decode(bytes)?;
                let job = p.request.spec.family();
                of_family(
                    ProcessPlan::KIND,
                    Family::Hobbing,
                    AnyPlan::Hobbing(Box::new(p)),
                    job,
                )
            }
            got => Err(CodecError::WrongKind {
                expected: Self::KINDS,
                got: got.to_string(),
            }),
        }
    }
}

/// A model of any family, as the template service and the agents receive it.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyModel {
    /// Hobbing.
    Hobbing(Box<MachiningModel>),
    /// Spiral face milling.
    Spiral(Box<SpiralModel>),
    /// Wire EDM.
    Wire(Box<WireModel>),
}

impl AnyModel {
    /// The job's id.
    pub fn job_id(&self) -> &JobId {
        match self {
            AnyModel::Hobbing(m) => &m.job_id,
            AnyModel::Spiral(m) => &m.job_id,
            AnyModel::Wire(m) => &m.job_id,
        }
    }

    /// The machine the model is for.
    pub fn machine(&self) -> &MachineId {
        match self {
            AnyModel::Hobbing(m) => &m.plan.machine.id,
            AnyModel::Spiral(m) => &m.plan.machine.id,
            AnyModel::Wire(m) => &m.plan.machine.id,
        }
    }
}

impl Incoming for AnyModel {
    const KINDS: &'static str = "machining_model, spiral_model or wire_model";
    fn decode_incoming(bytes: &[u8]) -> Result<Self, CodecError> {
        match kind_of(bytes, Self::KINDS)?.as_str() {
            WireModel::KIND => {
                let m: WireModel = decode(bytes)?;
                let job = m.plan.request.spec.family();
                of_family(
                    WireModel::KIND,
                    Family::WireEdm,
                    AnyModel::Wire(Box::new(m)),
                    job,
                )
            }
            SpiralModel::KIND => {
                let m: SpiralModel = decode(bytes)?;
                let job = m.plan.request.spec.family();
                of_family(
                    SpiralModel::KIND,
                    Family::SpiralFace,
                    AnyModel::Spiral(Box::new(m)),
                    job,
                )
            }
            MachiningModel::KIND => {
                let m: MachiningModel = decode(bytes)?;
                let job = m.plan.request.spec.family();
                of_family(
                    MachiningModel::KIND,
                    Family::Hobbing,
                    AnyModel::Hobbing(Box::new(m)),
                    job,
                )
            }
            got => Err(CodecError::WrongKind {
                expected: Self::KINDS,
                got: got.to_string(),
            }),
        }
    }
}

/// Refuses a plan or model of one family whose job is of another: the
/// stages after the knowledge service read the family's sections from the
/// job the plan carries.
fn of_family<T>(
    what: &'static str,
    family: Family,
    decoded: T,
    job: Family,
) -> Result<T, CodecError> {
    if job == family {
        Ok(decoded)
    } else {
        Err(CodecError::Malformed {
            expected_kind: what,
            detail: format!(
                "a {what} carries a {} job; it is made for a {} job only",
                job.as_str(),
                family.as_str()
            ),
        })
    }
}
