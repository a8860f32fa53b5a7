//! The simulation of the electronic gearbox (840D EGDEF/EGON/EGONSYNE/EGOFS/EGDEL,
//! FANUC G81/G80), and the end-of-program checks.

use super::*;

impl<'m> Sim<'m> {
    pub(super) fn is_table(&mut self, line: u32, call: &str, following: AxisName) -> bool {
        if self.role(&following) == Role::C {
            return true;
        }
        let table = &self.profile.axes.table;
        let msg = format!(
            "{call} names {following} as the following axis; this machine's table axis is {table}"
        );
        self.push(line, Code::COUPLING_RATIO, msg);
        false
    }

    pub(super) fn lead_index(role: Role) -> Option<usize> {
        match role {
            Role::B => Some(0),
            Role::Z => Some(1),
            Role::Y => Some(2),
            _ => None,
        }
    }

    pub(super) fn bad_lead(&mut self, line: u32, call: &str, axis: AxisName, first: bool) {
        let ax = &self.profile.axes;
        let msg = if first {
            format!(
                "the first leading axis of {call} is {axis}, not the hob axis {}",
                ax.hob
            )
        } else {
            format!(
                "{axis} is not a leading axis of the hobbing gearbox (hob {}, axial {}, shift {})",
                ax.hob, ax.axial, ax.shift
            )
        };
        self.push(line, Code::COUPLING_RATIO, msg);
    }

    pub(super) fn egdef(&mut self, line: u32, following: AxisName, leading: &[(AxisName, i64)]) {
        self.is_table(line, "EGDEF", following);
        if self.coupled.is_some() {
            self.push(
                line,
                Code::COUPLING_RATIO,
                "EGDEF redefines the gearbox while it is coupled; EGOFS first".into(),
            );
        }
        let mut leads = [false; 3];
        for (i, (axis, _)) in leading.iter().enumerate() {
            let role = self.role(axis);
            match Self::lead_index(role) {
                Some(k) if (k == 0) == (i == 0) => leads[k] = true,
                _ => self.bad_lead(line, "EGDEF", *axis, i == 0),
            }
        }
        self.definition = Some(Definition { leads });
        self.defined = true;
    }

    pub(super) fn egon(
        &mut self,
        line: u32,
        sync: bool,
        position: Option<Num>,
        following: AxisName,
        leading: &[Lead],
    ) {
        let call = if sync { "EGONSYNE" } else { "EGON" };
        self.is_table(line, call, following);
        if self.coupled.is_some() {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!("{call} while the gearbox is already coupled; EGOFS first"),
            );
        }
        let unit_start = !self.started || self.defined;
        if unit_start && self.started {
            self.unit = (self.unit + 1).min(self.units.len() - 1);
        }
        self.defined = false;
        // Every coupling of one unit must share one reference: couple at the
        // same synchronised positions, or stay coupled. A plain EGON takes
        // wherever the axes stand as its reference.
        let positions: Option<Vec<f64>> = sync.then(|| {
            std::iter::once(position.map_or(0.0, |p| p.value))
                .chain(leading.iter().map(|l| l.position.map_or(0.0, |p| p.value)))
                .collect()
        });
        if unit_start {
            self.reference = Some((line, positions));
        } else if let Some((first, reference)) = self.reference.clone() {
            let same = match (&reference, &positions) {
                (Some(a), Some(b)) => {
                    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= TOL)
                }
                _ => false,
            };
            if !same {
                let why = match (&reference, &positions) {
                    (None, _) => format!("the coupling of line {first} was a plain EGON, whose reference is wherever the axes stood"),
                    (_, None) => "a plain EGON takes wherever the axes stand as its reference".to_string(),
                    _ => format!("its synchronised positions differ from those of line {first}"),
                };
                self.push(
                    line,
                    Code::COUPLING_RATIO,
                    format!("{call} couples this unit again, but {why}: the cut lands in new gaps (couple every cut at the same EGONSYNE positions, or stay coupled)"),
                );
            }
        }
        self.started = true;
        let mut leads = [false; 3];
        for l in leading {
            if let Some(k) = Self::lead_index(self.role(&l.axis)) {
                leads[k] = true;
            }
        }
        match self.definition {
            None => self.push(
                line,
                Code::COUPLING_RATIO,
                format!("{call} switches on a gearbox that EGDEF has not defined"),
            ),
            Some(def) if def.leads != leads => self.push(
                line,
                Code::COUPLING_RATIO,
                format!("the leading axes of {call} differ from those of the EGDEF"),
            ),
            Some(_) => {}
        }
        let active = self.check_leads(line, call, leading);
        self.trace.couplings.push(TraceCoupling {
            line,
            num: active.num,
            den: active.den,
            c_per_z_deg_per_mm: active.z,
            c_per_y_deg_per_mm: active.y,
            unit_start,
            synchronised: sync,
        });
        self.coupled = Some(active);
        self.check_table_speed(line);
    }

    /// The 840D coupling against the unit's model.
    pub(super) fn check_leads(&mut self, line: u32, call: &str, leading: &[Lead]) -> Active {
        let k = self.unit().kin;
        // The programmed ratio: the hob's hand in the machine's directions.
        let (z0, z) = (k.factors.c_per_b.num, k.factors.c_per_b.den);
        let mut active = Active {
            num: 0,
            den: 1,
            z: None,
            y: None,
        };
        let (_, zn, yn) = self.axes();
        for (i, l) in leading.iter().enumerate() {
            let role = self.role(&l.axis);
            if i == 0 {
                if role != Role::B {
                    self.bad_lead(line, call, l.axis, true);
                }
                let (num, den) = (l.num.integer().unwrap_or(0), l.den.integer().unwrap_or(0));
                (active.num, active.den) = (num, den);
                let lhs = i128::from(num) * i128::from(z);
                let rhs = i128::from(den) * i128::from(z0);
                if lhs != rhs || den == 0 {
                    let table = &self.profile.axes.table;
                    let hob = &self.profile.axes.hob;
                    self.push(
                        line,
                        Code::COUPLING_RATIO,
                        format!("{call} couples {table} to {hob} by {num}/{den}; the model's ratio is {z0}/{z} (z0/z signed by the hob's hand in the machine's axis directions)"),
                    );
                }
                continue;
            }
            if l.den.integer() != Some(1) {
                self.push(
                    line,
                    Code::COUPLING_RATIO,
                    format!(
                        "the factor of {} is written as numerator with denominator 1",
                        l.axis
                    ),
                );
            }
            let f = l.num.value;
            let (slot, want, what, axis) = match role {
                Role::Z => (
                    &mut active.z,
                    k.factors.c_per_z_deg_per_mm,
                    "differential",
                    zn,
                ),
                Role::Y => (
                    &mut active.y,
                    k.factors.c_per_y_deg_per_mm,
                    "shift compensation",
                    yn,
                ),
                _ => {
                    self.bad_lead(line, call, l.axis, false);
                    continue;
                }
            };
            *slot = Some(f);
            if (f - want).abs() > FACTOR {
                self.push(
                    line,
                    Code::COUPLING_RATIO,
                    format!(
                        "the {axis} factor {} deg/mm of {call} differs from the model's {what} {} deg/mm",
                        f6(f),
                        f6(want)
                    ),
                );
            }
        }
        let diff = k.factors.c_per_z_deg_per_mm;
        if active.z.is_none() && diff.abs() > FACTOR {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!(
                    "{call} has no {zn} factor, but the model's differential is {} deg/mm",
                    f6(diff)
                ),
            );
        }
        active
    }

    /// FANUC G81: the gearbox couples the table to the hob by T teeth and L
    /// hob starts, with the helical compensation Q (module) and P (helix
    /// angle); a coupling from the uncoupled state starts the next unit.
    pub(super) fn g81(
        &mut self,
        line: u32,
        teeth: Num,
        starts: Num,
        module: Option<Num>,
        helix: Option<Num>,
    ) {
        let unit_start = self.coupled.is_none();
        if unit_start {
            if self.started {
                self.unit = (self.unit + 1).min(self.units.len() - 1);
            }
            self.started = true;
        }
        let t = teeth.integer().unwrap_or(0);
        let l = starts.integer().unwrap_or(0);
        self.check_g81_ratio(line, t, l);
        let implied = self.check_g81_helical(line, t, module, helix);
        let active = Active {
            num: l,
            den: t,
            z: implied,
            y: None,
        };
        self.trace.couplings.push(TraceCoupling {
            line,
            num: l,
            den: t,
            c_per_z_deg_per_mm: implied,
            c_per_y_deg_per_mm: None,
            unit_start,
            synchronised: false,
        });
        self.coupled = Some(active);
        self.check_table_speed(line);
    }

    /// G81 T and L against the unit's model: T is the gear's teeth and L the
    /// hob's starts themselves (the model keeps z0/z reduced), L signed by
    /// the table's direction against the hob.
    fn check_g81_ratio(&mut self, line: u32, t: i64, l: i64) {
        let u = self.unit();
        let k = u.kin;
        let (z0, z) = (u.hob.starts, u.gear.teeth);
        if !(1..=1000).contains(&t) {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!("G81 T{t}: T is 1 to 1000"),
            );
        } else if t != i64::from(z) {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!("G81 T{t}: T must be the gear's {z} teeth"),
            );
        }
        if l == 0 || l.abs() > 21 {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!("G81 L{l}: L is 1 to 21 with the sign of the direction"),
            );
        } else if l.unsigned_abs() != u64::from(z0) {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!("G81 L{l}: |L| must be the hob's {z0} starts"),
            );
        } else if (l < 0) != (k.factors.c_per_b.num < 0) {
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!(
                    "G81 L{l}: the sign of L is the table's direction against the hob, which the hob's hand ({}) fixes on this machine: L{}",
                    match u.hob.hand {
                        gearcam_proto::Hand::Right => "right",
                        gearcam_proto::Hand::Left => "left",
                    },
                    if k.factors.c_per_b.num < 0 { -l.abs() } else { l.abs() }
                ),
            );
        }
    }

    /// G81 Q and P against the model's differential: both or neither, Q the
    /// gear's normal module and |P| its helix angle, P signed like the
    /// differential. Returns the C per Z (deg/mm) that Q, P and T imply.
    fn check_g81_helical(
        &mut self,
        line: u32,
        t: i64,
        module: Option<Num>,
        helix: Option<Num>,
    ) -> Option<f64> {
        let u = self.unit();
        let diff = u.kin.factors.c_per_z_deg_per_mm;
        let mut implied = None;
        match (module, helix) {
            (Some(q), Some(p)) => {
                let (q, p) = (q.value, p.value);
                if q * t as f64 != 0.0 {
                    implied = Some(360.0 * p.to_radians().sin() / (PI * q * t as f64));
                }
                let mn = u.gear.module_mm;
                let beta = u.gear.helix_angle_deg.abs();
                let msg = if !(0.1..=25.0).contains(&q) || p.abs() > 90.0 {
                    Some(format!(
                        "G81 Q{} P{}: Q is 0.1 to 25 mm and |P| at most 90 degrees",
                        f3(q),
                        f4(p)
                    ))
                } else if diff.abs() <= FACTOR {
                    Some(format!(
                        "G81 Q{} P{} adds a helical compensation, but the model has no differential",
                        f3(q),
                        f4(p)
                    ))
                } else if (q - mn).abs() > MM {
                    Some(format!(
                        "G81 Q{}: Q must be the gear's normal module {} mm",
                        f3(q),
                        f3(mn)
                    ))
                } else if (p.abs() - beta).abs() > DEG {
                    Some(format!(
                        "G81 P{}: |P| must be the gear's helix angle {} degrees",
                        f4(p),
                        f4(beta)
                    ))
                } else if (p > 0.0) != (diff > 0.0) {
                    Some(format!(
                        "G81 P{} compensates {} deg/mm of C per Z; the model's differential is {} deg/mm, so P is {}",
                        f4(p),
                        f6(implied.unwrap_or(0.0)),
                        f6(diff),
                        f4(beta.copysign(diff))
                    ))
                } else {
                    None
                };
                if let Some(msg) = msg {
                    self.push(line, Code::COUPLING_RATIO, msg);
                }
            }
            (None, None) if diff.abs() > FACTOR => self.push(
                line,
                Code::COUPLING_RATIO,
                format!(
                    "G81 without Q and P: the model's differential of {} deg/mm needs the helical compensation (Q the module, P the helix angle)",
                    f6(diff)
                ),
            ),
            (None, None) => {}
            _ => self.push(
                line,
                Code::COUPLING_RATIO,
                "G81 takes Q and P together (alarm PS0594 otherwise)".into(),
            ),
        }
        implied
    }

    pub(super) fn gear_off(&mut self, line: u32, following: Option<AxisName>) {
        let call = match following {
            Some(f) => {
                self.is_table(line, "EGOFS", f);
                format!("EGOFS({f})")
            }
            None => "G80".to_string(),
        };
        if self.coupled.is_some() {
            if let Some(zone) = self.zone_here() {
                let zone_text = zone.describe(self.axes(), self.units.len());
                self.push(
                    line,
                    Code::DEPTH_UNCOUPLED,
                    format!("{call} uncouples the gearbox with the hob inside the contact zone ({zone_text})"),
                );
            }
        }
        self.coupled = None;
    }

    pub(super) fn egdel(&mut self, line: u32, following: AxisName) {
        self.is_table(line, "EGDEL", following);
        if self.coupled.is_some() {
            self.push(
                line,
                Code::COUPLING_RATIO,
                "EGDEL deletes the gearbox definition while it is coupled; EGOFS first".into(),
            );
        }
        self.definition = None;
    }

    // ----- end -----

    pub(super) fn finish(&mut self, last_line: u32) {
        let end_code = self.profile.mcodes.program_end;
        let end_line = match self.end {
            Some(l) => l,
            None => {
                self.push(
                    last_line,
                    Code::END_AT_A,
                    format!(
                        "the program does not end with M{end_code}, the machine's end of program"
                    ),
                );
                last_line
            }
        };
        for (name, on) in FUNCTIONS.iter().zip(self.functions) {
            if let Some(since) = on {
                self.push(
                    end_line,
                    Code::MCODE_PAIR,
                    format!("{name} is still on at the end of the program (switched on at line {since})"),
                );
            }
        }
        if let Some(line) = self.last_move {
            let (hx, hz) = (self.profile.home_x_mm, self.profile.home_z_mm);
            if (self.x - hx).abs() > MM || (self.z - hz).abs() > MM {
                let (xn, zn, _) = self.axes();
                let msg = format!(
                    "the last move ends at {xn}={} {zn}={}, not at the start point A ({xn}={} {zn}={})",
                    f3(self.x),
                    f3(self.z),
                    f3(hx),
                    f3(hz)
                );
                self.push(line, Code::END_AT_A, msg);
            }
        }
    }
}
