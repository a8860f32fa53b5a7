//! The simulation of axis motion: the G-code system and set-up, travel limits, feeds,
//! contact zones crossed by rapids, and the shift moves.

use super::*;

/// Where a motion block sends the axes: the end point, which of X, Z and Y
/// the block names, the swivel A and the FANUC shift move's C correction.
struct Target {
    x: f64,
    z: f64,
    y: f64,
    x_set: bool,
    z_set: bool,
    y_set: bool,
    a: Option<f64>,
    c: Option<f64>,
}

impl<'m> Sim<'m> {
    /// One motion block: its modal words take effect; a block that moves is
    /// read, checked (dimensions, path, travel, feed, contact zone, shift)
    /// and traced, and the axes stand at its end point.
    pub(super) fn motion(&mut self, line: u32, m: &Motion) {
        self.motion_modes(line, m);
        if m.words().is_empty() {
            return;
        }
        let Some(interp) = self.interp else {
            self.push(
                line,
                Code::PARSE,
                "a move without G0 or G1 in effect".into(),
            );
            return;
        };
        let inc = self.incremental.is_some();
        let Some(t) = self.target(line, m, inc) else {
            return;
        };
        let shift_form = inc
            && interp == Interp::Linear
            && t.y_set
            && t.c.is_some()
            && !t.x_set
            && !t.z_set
            && t.a.is_none();
        if !self.check_distance(line, shift_form, inc, t.c) {
            return;
        }
        let kind = match interp {
            Interp::Rapid => MoveKind::Rapid,
            Interp::Linear => MoveKind::Feed,
            _ => MoveKind::Arc,
        };
        let from = [self.x, self.z, self.y];
        let to = [t.x, t.z, t.y];
        let Some(path) = self.path(line, m, interp, from, to) else {
            return;
        };
        self.check_travel(line, &t);
        let feed = if kind == MoveKind::Rapid {
            None
        } else {
            self.check_feed(line);
            self.feed
        };
        let coupled = self.coupled.is_some();
        self.check_zone(line, interp, kind, &path, from, to);

        let dy = t.y - self.y;
        if shift_form {
            self.check_shift_correction(line, dy, t.c.unwrap_or(0.0));
        } else if dy.abs() > TOL && coupled {
            self.check_coupled_shift(line, from[2], t.y);
        }

        self.trace.moves.push(TraceMove {
            line,
            kind,
            x_mm: t.x,
            z_mm: t.z,
            y_mm: t.y,
            feed_mm_min: feed,
            dwell_s: None,
            coupled,
            c_correction_deg: t.c,
            arc: path.arc,
        });
        (self.x, self.z, self.y) = (t.x, t.z, t.y);
        self.last_move = Some(line);
    }

    /// The modal part of a motion block, which holds whether or not the
    /// block moves: the set-up words, the G-code system and (before the
    /// first move) the set-up check, the interpolation, absolute or
    /// incremental dimensions and the feed.
    fn motion_modes(&mut self, line: u32, m: &Motion) {
        self.setup.merge(m.setup);
        self.check_system(line, m);
        if !self.setup_checked && !m.words().is_empty() {
            self.setup_checked = true;
            self.check_setup(line);
        }
        if let Some(i) = m.interp {
            self.interp = Some(i);
        }
        match m.distance {
            Some(Distance::Incremental) => self.incremental = Some(line),
            Some(Distance::Absolute) => self.incremental = None,
            None => {}
        }
        if let Some(f) = m.feed {
            self.feed = Some(f.value);
        }
    }

    /// The block's axis words evaluated into its end point, absolute or
    /// added to where the axes stand. `None` (with a finding) when a value
    /// cannot be computed, a length has more than 3 decimals or a word
    /// names an axis that a motion block does not move.
    fn target(&mut self, line: u32, m: &Motion, inc: bool) -> Option<Target> {
        let mut t = Target {
            x: self.x,
            z: self.z,
            y: self.y,
            x_set: false,
            z_set: false,
            y_set: false,
            a: None,
            c: None,
        };
        for w in m.words() {
            let v = match w.value.eval(&self.vars) {
                Ok(v) => v,
                Err(e) => {
                    self.push(
                        line,
                        Code::PARSE,
                        format!("the value of {} cannot be computed: {e}", w.axis),
                    );
                    return None;
                }
            };
            let role = self.role(&w.axis);
            if let Some(n) = w.value.literal() {
                if n.decimals > 3 && !matches!(role, Role::A | Role::C) {
                    self.push(
                        line,
                        Code::PARSE,
                        format!(
                            "{} has {} decimals; lengths are written with at most 3",
                            w.axis, n.decimals
                        ),
                    );
                    return None;
                }
            }
            let base = |old: f64| if inc { old + v } else { v };
            match role {
                Role::X => (t.x, t.x_set) = (base(self.x), true),
                Role::Z => (t.z, t.z_set) = (base(self.z), true),
                Role::Y => (t.y, t.y_set) = (base(self.y), true),
                Role::A => t.a = Some(base(self.a.unwrap_or(0.0))),
                Role::C if self.dialect == Dialect::Fanuc => t.c = Some(v),
                _ => {
                    let ax = &self.profile.axes;
                    let msg = format!(
                        "{} is not an axis a motion block moves (this machine's are {} {} {} {})",
                        w.axis, ax.radial, ax.axial, ax.shift, ax.swivel
                    );
                    self.push(line, Code::PARSE, msg);
                    return None;
                }
            }
        }
        Some(t)
    }

    /// Incremental dimensions and C belong only to the FANUC shift move
    /// G01 G91 Y.. C..; any other use is a finding and the block is not
    /// run (false).
    fn check_distance(&mut self, line: u32, shift_form: bool, inc: bool, c: Option<f64>) -> bool {
        if let Some(g91) = self.incremental.filter(|_| !shift_form) {
            let since = if g91 == line {
                String::new()
            } else {
                format!(" (G91 of line {g91} is still in effect; write G90)")
            };
            self.push(
                line,
                Code::PARSE,
                format!("incremental dimensions are used only for the shift move G01 G91 Y.. C..{since}"),
            );
            return false;
        }
        if c.is_some() && !inc {
            self.push(
                line,
                Code::PARSE,
                "C is programmed only in the incremental shift move G01 G91 Y.. C..".into(),
            );
            return false;
        }
        true
    }

    /// The path the tool takes from `from` to `to`: a line for G0 and G1,
    /// the arc, sampled, for CIP (through its intermediate point) and
    /// G02/G03 (by its radius). `None` (with a finding) when the arc is not fully given or
    /// cannot be drawn.
    fn path(
        &mut self,
        line: u32,
        m: &Motion,
        interp: Interp,
        from: [f64; 3],
        to: [f64; 3],
    ) -> Option<Path> {
        match interp {
            Interp::Rapid | Interp::Linear => Some(Path::line(from, to)),
            Interp::CircleVia => {
                let Some((vx, vz)) = m.via else {
                    self.push(
                        line,
                        Code::PARSE,
                        "CIP is in effect, but the block has no intermediate point I1= K1=".into(),
                    );
                    return None;
                };
                self.travel(line, Role::X, vx.value);
                self.travel(line, Role::Z, vz.value);
                match circle_via((from[1], from[0]), (vz.value, vx.value), (to[1], to[0])) {
                    Some((centre, t0, sweep)) => Some(Path::arc(from, to, centre, t0, sweep)),
                    None => {
                        self.push(
                            line,
                            Code::PARSE,
                            "the start, intermediate and end point of the CIP lie on one line"
                                .into(),
                        );
                        None
                    }
                }
            }
            Interp::ArcCw | Interp::ArcCcw => self.arc_path(line, m, interp, from, to),
        }
    }

    /// The G02/G03 arc by its radius R, in the X-Z plane (which a FANUC
    /// control cuts only after G18).
    fn arc_path(
        &mut self,
        line: u32,
        m: &Motion,
        interp: Interp,
        from: [f64; 3],
        to: [f64; 3],
    ) -> Option<Path> {
        if self.dialect == Dialect::Fanuc && !self.setup.plane_zx {
            self.push(
                line,
                Code::SETUP,
                "an arc in X and Z before G18: a FANUC control starts in G17, the X-Y plane, and would not cut this arc in X and Z".into(),
            );
            return None;
        }
        let Some(r) = m.radius.map(|r| r.value) else {
            self.push(
                line,
                Code::PARSE,
                "G02/G03 is in effect, but the block has no radius R".into(),
            );
            return None;
        };
        let ccw = interp == Interp::ArcCcw;
        match arc_radius((from[1], from[0]), (to[1], to[0]), r, ccw) {
            Some((centre, t0, sweep)) => Some(Path::arc(from, to, centre, t0, sweep)),
            None => {
                self.push(
                    line,
                    Code::PARSE,
                    format!(
                        "the arc radius R{} cannot join its start and end point",
                        f3(r)
                    ),
                );
                None
            }
        }
    }

    /// The named X and Z against the machine's travel, and a swivel A
    /// against its largest swivel about the set-up's offset; the swivel is
    /// traced and taken.
    fn check_travel(&mut self, line: u32, t: &Target) {
        if t.x_set {
            self.travel(line, Role::X, t.x);
        }
        if t.z_set {
            self.travel(line, Role::Z, t.z);
        }
        if let Some(a) = t.a {
            let max = self.profile.limits.max_swivel_deg;
            if (a - self.profile.settings.swivel_offset_deg).abs() > max + DEG {
                let name = &self.profile.axes.swivel;
                self.push(
                    line,
                    Code::TRAVEL_LIMIT,
                    format!(
                        "swivel {name}={} is beyond the machine's limit of ±{} degrees about {}",
                        f4(a),
                        f4(max),
                        f4(self.profile.settings.swivel_offset_deg)
                    ),
                );
            }
            self.trace.swivel_deg.push((line, a));
            self.a = Some(a);
        }
    }

    /// A move into the contact zone: a rapid may never pass through the
    /// blank, and no move may enter it unless the gearbox is coupled and
    /// the hob turning.
    fn check_zone(
        &mut self,
        line: u32,
        interp: Interp,
        kind: MoveKind,
        path: &Path,
        from: [f64; 3],
        to: [f64; 3],
    ) {
        // A move that only increases X is a radial withdrawal: it can leave
        // the zone (a worm wheel's D → E retract from the throat) but never
        // enter it.
        let withdrawal = to[0] > from[0]
            && (to[1] - from[1]).abs() <= TOL
            && (to[2] - from[2]).abs() <= TOL
            && matches!(interp, Interp::Rapid | Interp::Linear);
        let zone = if withdrawal {
            None
        } else {
            self.zone_crossed(path)
        };
        let why = match (self.coupled.is_some(), self.turning()) {
            (true, true) => None,
            (false, true) => Some("the gearbox is not coupled"),
            (true, false) => Some("the hob is not turning"),
            (false, false) => Some("the gearbox is not coupled and the hob is not turning"),
        };
        if let Some(zone) = zone.filter(|_| kind == MoveKind::Rapid || why.is_some()) {
            let what = self.move_text(kind, from, to);
            let zone_text = zone.describe(self.axes(), self.units.len());
            if kind == MoveKind::Rapid {
                self.push(
                    line,
                    Code::RAPID_CLEARANCE,
                    format!("{what} passes through the blank zone ({zone_text})"),
                );
            }
            if let Some(why) = why {
                self.push(
                    line,
                    Code::DEPTH_UNCOUPLED,
                    format!("{what} enters the contact zone ({zone_text}) while {why}"),
                );
            }
        }
    }

    /// The program's G codes mean what the machine's G-code system says:
    /// FANUC M series and T systems B and C take G94 for feed per minute
    /// (G98 is a canned-cycle return level there); T system A takes G98 and
    /// has no G90/G91 (G90 is a turning cycle).
    pub(super) fn check_system(&mut self, line: u32, m: &Motion) {
        use gearcam_proto::GCodeSystem as S;
        let system = self.profile.gcode_system;
        match (self.dialect, system) {
            (Dialect::Fanuc, S::FanucM | S::FanucTB | S::FanucTC) if m.feed_code == Some(98) => {
                self.push(
                    line,
                    Code::SETUP,
                    format!("G98 is the canned-cycle return level in G-code system {}, not feed per minute: write G94", system.as_str()),
                );
            }
            (Dialect::Fanuc, S::FanucTA) if m.distance.is_some() || m.feed_code == Some(94) => {
                self.push(
                    line,
                    Code::SETUP,
                    "G-code system A (fanuc_t_a) has no G90/G91 or G94: absolute is X/Z, incremental U/W, feed per minute G98".into(),
                );
            }
            (Dialect::Fanuc, S::Sinumerik)
            | (Dialect::Sinumerik840d, S::FanucM | S::FanucTA | S::FanucTB | S::FanucTC) => {
                self.push(
                    line,
                    Code::SETUP,
                    format!(
                        "the machine profile names G-code system {} for a {} control",
                        system.as_str(),
                        self.dialect.as_str()
                    ),
                );
            }
            _ => {}
        }
    }

    /// Before the first move the program states the metric unit, the
    /// machine's work offset (Z0 on the table, X0 on its axis) and, on an
    /// 840D, that X is a radius.
    pub(super) fn check_setup(&mut self, line: u32) {
        let s = self.setup;
        let (metric, offset) = match self.dialect {
            Dialect::Fanuc => ("G21", "work offset"),
            _ => ("G71", "work offset"),
        };
        let want = self.profile.work_offset.trim().to_ascii_uppercase();
        let want_n = want
            .strip_prefix('G')
            .and_then(|n| n.parse::<u8>().ok())
            .filter(|n| (54..=59).contains(n));
        let mut missing = Vec::new();
        if !s.metric {
            missing.push(format!("{metric} (metric input)"));
        }
        if want_n.is_some() && s.work_offset != want_n {
            missing.push(format!(
                "{want} ({offset}: Z0 on the table plane, X0 on the table axis)"
            ));
        }
        if self.dialect == Dialect::Sinumerik840d && !s.radius_x {
            missing.push("DIAMOF (X is the centre distance, a radius)".into());
        }
        if !missing.is_empty() {
            self.push(
                line,
                Code::SETUP,
                format!("the first move comes before {}", missing.join(", ")),
            );
        }
    }

    pub(super) fn move_text(&self, kind: MoveKind, from: [f64; 3], to: [f64; 3]) -> String {
        let (xn, zn, _) = self.axes();
        let what = match kind {
            MoveKind::Rapid => "rapid move",
            MoveKind::Feed => "feed move",
            MoveKind::Arc => "arc",
            MoveKind::Dwell => "dwell",
        };
        format!(
            "{what} from {xn}={} {zn}={} to {xn}={} {zn}={}",
            f3(from[0]),
            f3(from[1]),
            f3(to[0]),
            f3(to[1])
        )
    }

    /// The first zone the path passes through.
    pub(super) fn zone_crossed(&self, path: &Path) -> Option<Zone> {
        path.segments()
            .find_map(|(p, q)| self.zones.iter().find(|z| z.crossed_by(p, q)).copied())
    }

    /// The zone the hob stands in.
    pub(super) fn zone_here(&self) -> Option<Zone> {
        let p = [self.x, self.z, self.y];
        self.zones.iter().find(|z| z.crossed_by(p, p)).copied()
    }

    pub(super) fn travel(&mut self, line: u32, role: Role, v: f64) {
        let (name, [lo, hi]) = match role {
            Role::X => (&self.profile.axes.radial, self.profile.limits.x_mm),
            _ => (&self.profile.axes.axial, self.profile.limits.z_mm),
        };
        if !(v >= lo - MM && v <= hi + MM) {
            let msg = format!(
                "{name}={} is outside the machine's travel {} to {} mm",
                f3(v),
                f3(lo),
                f3(hi)
            );
            self.push(line, Code::TRAVEL_LIMIT, msg);
        }
    }

    pub(super) fn check_feed(&mut self, line: u32) {
        let max = self.profile.limits.max_axial_feed_mm_min;
        match self.feed {
            Some(f) if f > 0.0 && f <= max + MM => {}
            Some(f) if f > 0.0 => self.push(
                line,
                Code::FEED_LIMIT,
                format!(
                    "feed F={} mm/min is above the machine's largest feed {} mm/min",
                    f3(f),
                    f3(max)
                ),
            ),
            Some(_) => self.push(
                line,
                Code::FEED_LIMIT,
                "a feed move with a zero feed F".into(),
            ),
            None => self.push(
                line,
                Code::FEED_LIMIT,
                "a feed move without a feed F in effect".into(),
            ),
        }
    }

    /// FANUC: the C correction of the incremental shift move.
    pub(super) fn check_shift_correction(&mut self, line: u32, dy: f64, c: f64) {
        if self.coupled.is_none() {
            self.push(
                line,
                Code::COUPLING_RATIO,
                "the shift move G01 G91 Y.. C.. corrects C for a coupled gearbox, but the gearbox is not coupled".into(),
            );
            return;
        }
        let per_y = self.unit().kin.factors.c_per_y_deg_per_mm;
        let want = per_y * dy;
        if (c - want).abs() > DEG + per_y.abs() * MM {
            let (_, _, yn) = self.axes();
            let table = &self.profile.axes.table;
            self.push(
                line,
                Code::COUPLING_RATIO,
                format!(
                    "the correction {table}{} for the shift {yn}{} differs from the model's {} ({} deg/mm)",
                    f4(c),
                    f3(dy),
                    f4(want),
                    f6(per_y)
                ),
            );
        }
    }

    /// A Y move while coupled, outside the FANUC shift form.
    pub(super) fn check_coupled_shift(&mut self, line: u32, from: f64, to: f64) {
        let (_, _, yn) = self.axes();
        let table = &self.profile.axes.table;
        let msg = match self.dialect {
            Dialect::Fanuc => format!(
                "{yn} moves from {} to {} while the gearbox is coupled without its {table} correction; write G01 G91 {yn}.. {table}..",
                f3(from),
                f3(to)
            ),
            _ if self.coupled.is_some_and(|c| c.y.is_none()) => format!(
                "{yn} moves from {} to {} while {table} is coupled without the shift compensation ({yn} is not a leading axis of the gearbox)",
                f3(from),
                f3(to)
            ),
            _ => return,
        };
        self.push(line, Code::COUPLING_RATIO, msg);
    }

    // ----- M functions -----
}
