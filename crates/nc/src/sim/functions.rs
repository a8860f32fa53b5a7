//! The simulation of switched machine functions (M codes) and spindle speeds.

use super::*;

impl<'m> Sim<'m> {
    pub(super) fn function(&self, code: u16) -> Option<(usize, bool)> {
        let mc = &self.profile.mcodes;
        [
            (mc.outer_support_on, mc.outer_support_off),
            (mc.fixture_clamp, mc.fixture_unclamp),
            (mc.coolant_on, mc.coolant_off),
            (mc.chip_conveyor_on, mc.chip_conveyor_off),
            (mc.mist_on, mc.mist_off),
        ]
        .iter()
        .enumerate()
        .find_map(|(i, (on, off))| {
            if code == *on {
                Some((i, true))
            } else if code == *off {
                Some((i, false))
            } else {
                None
            }
        })
    }

    pub(super) fn mcode(&mut self, line: u32, code: u16, speed: Option<Num>) {
        self.trace.mcodes.push((line, code));
        let mc = &self.profile.mcodes;
        if let Some(s) = speed {
            self.speed = Some(s.value);
            self.trace.spindle_rpm.push((line, s.value));
            self.check_hob_speed(line, s.value);
        }
        if code == mc.spindle_on {
            if self.speed.is_none() {
                self.push(
                    line,
                    Code::SPEED_LIMIT,
                    format!("M{code} switches the hob on without a speed S"),
                );
            }
            self.spindle = true;
            self.check_table_speed(line);
        } else if code == mc.spindle_off {
            if let Some(zone) = self.zone_here() {
                let zone_text = zone.describe(self.axes(), self.units.len());
                self.push(
                    line,
                    Code::DEPTH_UNCOUPLED,
                    format!("M{code} stops the hob inside the contact zone ({zone_text})"),
                );
            }
            self.spindle = false;
        } else if code == mc.program_end {
            self.end = Some(line);
        } else if let Some((k, on)) = self.function(code) {
            let name = FUNCTIONS[k];
            match (on, self.functions[k]) {
                (true, Some(since)) => self.push(
                    line,
                    Code::MCODE_PAIR,
                    format!("M{code} switches {name} on, but it has been on since line {since}"),
                ),
                (true, None) => self.functions[k] = Some(line),
                (false, Some(_)) => self.functions[k] = None,
                (false, None) => self.push(
                    line,
                    Code::MCODE_PAIR,
                    format!("M{code} switches {name} off, but it is not on"),
                ),
            }
        } else if code != 0 {
            self.push(
                line,
                Code::PARSE,
                format!("M{code} is not one of the machine's M functions"),
            );
        } else {
            // M0: the operator reaches into the machine (a hob change).
            let on: Vec<String> = FUNCTIONS
                .iter()
                .zip(self.functions)
                .filter(|(name, since)| since.is_some() && STOP_OFF.contains(name))
                .map(|(name, since)| format!("{name} (on since line {})", since.unwrap_or(0)))
                .collect();
            if !on.is_empty() || self.spindle {
                let mut what = on;
                if self.spindle {
                    what.push("the hob spindle".into());
                }
                self.push(
                    line,
                    Code::MCODE_PAIR,
                    format!(
                        "M0 stops for the operator with {} still on; switch it off before the stop",
                        what.join(", ")
                    ),
                );
            }
        }
    }

    /// S printed with 3 decimals on 840D, a whole number on FANUC.
    pub(super) fn speed_tolerance(&self) -> f64 {
        if self.dialect == Dialect::Fanuc {
            1e-9
        } else {
            MM
        }
    }

    pub(super) fn check_hob_speed(&mut self, line: u32, s: f64) {
        let max = self.profile.limits.max_hob_rpm;
        if s > max + self.speed_tolerance() {
            self.push(
                line,
                Code::SPEED_LIMIT,
                format!(
                    "hob speed S={} rpm is above the machine's largest hob speed {} rpm",
                    f3(s),
                    f3(max)
                ),
            );
        }
    }

    /// The table speed S·z0/z, with the coupling in effect (or the model's).
    pub(super) fn check_table_speed(&mut self, line: u32) {
        let (true, Some(s)) = (self.spindle, self.speed) else {
            return;
        };
        let (num, den) = match self.coupled {
            Some(c) if c.den != 0 => (c.num.unsigned_abs() as f64, c.den.unsigned_abs() as f64),
            _ => {
                let r = self.unit().kin.coupling;
                (f64::from(r.num.unsigned_abs()), f64::from(r.den.max(1)))
            }
        };
        let ratio = num / den;
        let table = s * ratio;
        let max = self.profile.limits.max_table_rpm;
        if table > max + self.speed_tolerance() * ratio.max(1.0) {
            self.push(
                line,
                Code::SPEED_LIMIT,
                format!(
                    "hob speed S={} rpm turns the table at S*{num}/{den} = {} rpm, above the machine's largest table speed {} rpm",
                    f3(s),
                    f3(table),
                    f3(max)
                ),
            );
        }
    }

    // ----- gearbox -----
}
