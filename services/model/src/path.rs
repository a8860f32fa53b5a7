//! The X–Z(–Y) path of one cut for each gear class (docs/reference.md#class-models): the five
//! positions A–E and the moves between B and E.
//!
//! X is the radial centre distance, Z the hob-centre height, Y the hob shift.
//! Every builder starts at B (reached by a rapid move the template writes) and
//! lists the moves to E; a move names only the axes it changes.

use gearcam_proto::{CrowningShape, LargeEnd, Move, MoveKind, Position, Positions, WormInfeed};

/// Chords a parabolic crowning may use at most; a tolerance that needs more is
/// refused by validation.
pub const MAX_CHORDS: u32 = 2000;

/// Default chord tolerance of a parabolic crowning, mm.
pub const DEFAULT_CHORD_TOLERANCE_MM: f64 = 0.001;

/// The heights and X of one cut, as the class builders need them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CutFrame {
    /// Start/end point A.
    pub home: Position,
    /// Finishing X of this cut at the reference section (L + Δx), mm.
    pub xc_mm: f64,
    /// Lower tooth face H, mm.
    pub bottom_face_mm: f64,
    /// Face width b, mm.
    pub face_width_mm: f64,
    /// ΔH′ + safety above the top face, mm.
    pub over_top_mm: f64,
    /// ΔH′ + safety below the bottom face, mm (differs from the top only on a
    /// cone, whose blank is smaller at one end).
    pub over_bottom_mm: f64,
    /// Safety distance, mm.
    pub safety_mm: f64,
    /// X lift of B over C, mm.
    pub retract_mm: f64,
    /// X lift of E over D, mm.
    pub exit_mm: f64,
    /// True for conventional cutting (feeds down), false for climb (feeds up).
    pub down: bool,
    /// Axial feed rate, mm/min.
    pub axial_feed_mm_min: f64,
    /// Radial feed rate, mm/min.
    pub radial_feed_mm_min: f64,
    /// Hob shift of this cut, when shifting.
    pub shift_mm: Option<f64>,
    /// X with the hob tip just clear of the blank, (Da1 + da0)/2 + Δx + safety, mm.
    pub clear_x_mm: f64,
}

impl CutFrame {
    /// Top face H + b.
    pub fn top_face_mm(&self) -> f64 {
        self.bottom_face_mm + self.face_width_mm
    }

    /// (start, end) heights of the axial feed: conventional from above the top
    /// face to below the bottom face, climb the reverse.
    pub fn stroke(&self) -> (f64, f64) {
        let top = self.top_face_mm() + self.over_top_mm;
        let bottom = self.bottom_face_mm - self.over_bottom_mm;
        if self.down {
            (top, bottom)
        } else {
            (bottom, top)
        }
    }
}

/// Positions and moves of one cut.
#[derive(Debug, Clone, PartialEq)]
pub struct CutPath {
    /// A–E.
    pub positions: Positions,
    /// The moves from B to E.
    pub moves: Vec<Move>,
}

fn mv(kind: MoveKind, x: Option<f64>, z: Option<f64>, feed: f64, note: &str) -> Move {
    Move {
        kind,
        x_mm: x,
        z_mm: z,
        y_mm: None,
        feed_mm_min: feed,
        via: None,
        radius_mm: None,
        dwell_s: 0.0,
        note: note.into(),
    }
}

fn p(x_mm: f64, z_mm: f64) -> Position {
    Position { x_mm, z_mm }
}

fn positions(f: &CutFrame, c: Position, d: Position) -> Positions {
    Positions {
        A: f.home,
        B: p(c.x_mm + f.retract_mm, c.z_mm),
        C: c,
        D: d,
        E: p(d.x_mm + f.exit_mm, d.z_mm),
    }
}

/// The first move of a cut: rapid infeed in X (with the shift, if any).
fn infeed(f: &CutFrame, x: f64, note: &str) -> Move {
    let mut m = mv(MoveKind::Rapid, Some(x), None, 0.0, note);
    m.y_mm = f.shift_mm;
    m
}

/// C → D: the axial feed through the face width to D.
fn axial_feed(f: &CutFrame, d: Position) -> Move {
    mv(
        MoveKind::Feed,
        None,
        Some(d.z_mm),
        f.axial_feed_mm_min,
        "C -> D: AXIAL FEED",
    )
}

/// D → E: the rapid radial retract by the exit distance.
fn retract(f: &CutFrame, d: Position) -> Move {
    mv(
        MoveKind::Rapid,
        Some(d.x_mm + f.exit_mm),
        None,
        0.0,
        "D -> E: RETRACT",
    )
}

/// Cylindrical gear, axial infeed (patent): B → C rapid in X, C → D axial feed,
/// D → E rapid in X.
pub fn axial(f: &CutFrame) -> CutPath {
    let (start, end) = f.stroke();
    let c = p(f.xc_mm, start);
    let d = p(f.xc_mm, end);
    let moves = vec![
        infeed(f, c.x_mm, "B -> C: INFEED TO DEPTH"),
        axial_feed(f, d),
        retract(f, d),
    ];
    CutPath {
        positions: positions(f, c, d),
        moves,
    }
}

/// Cylindrical gear, radial-axial infeed: the hob plunges radially at the
/// entry face (hob centre `safety` outside it) from just clear of the blank to
/// depth at the radial feed, then feeds axially through the face width and
/// the clearance ΔH′ on the exit side.
pub fn radial_axial(f: &CutFrame) -> CutPath {
    let (_, end) = f.stroke();
    let entry = if f.down {
        f.top_face_mm() + f.safety_mm
    } else {
        f.bottom_face_mm - f.safety_mm
    };
    let c = p(f.xc_mm, entry);
    let d = p(f.xc_mm, end);
    let moves = vec![
        infeed(
            f,
            f.clear_x_mm,
            "B -> PLUNGE START: HOB TIP CLEAR OF THE BLANK",
        ),
        mv(
            MoveKind::Feed,
            Some(c.x_mm),
            None,
            f.radial_feed_mm_min,
            "PLUNGE -> C: RADIAL FEED TO DEPTH",
        ),
        axial_feed(f, d),
        retract(f, d),
    ];
    CutPath {
        positions: positions(f, c, d),
        moves,
    }
}

/// X change per mm of Z upwards along a cone of angle δ: the radius shrinks
/// towards the small end, so −tan δ with the large end at the bottom.
pub fn cone_slope(angle_deg: f64, large_end: LargeEnd) -> f64 {
    let t = angle_deg.to_radians().tan();
    match large_end {
        LargeEnd::Bottom => -t,
        LargeEnd::Top => t,
    }
}

/// The hob as a conical path needs it: its tip radius ra0 and its
/// reference radius r0 (where its tooth and space are equally wide), mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HobRadii {
    /// Tip radius ra0, mm.
    pub tip_mm: f64,
    /// Reference radius r0 = z0·mn / (2·sin γ0), mm.
    pub reference_mm: f64,
}

/// How a hob fed along a cone of angle δ cuts. Its envelope, a solid of
/// revolution about its own axis (across the XZ plane) swept along the
/// cone line, is the sweep of its axial section along that line: every hob
/// radius ρ lies ρ from the hob's centre line, normal to it, so ρ/cos δ
/// from it along X. In a transverse section the hob's rack therefore stands
/// with its depths stretched by 1/cos δ: its reference line at
/// X − r0/cos δ, its tip at X − ra0/cos δ, its flanks at tan α′ = tan αn·cos δ
/// (for a spur gear; the widths along the hob axis are unchanged). And the
/// radius ρ touches its envelope at the point of its circle normal to the
/// line, ρ·sin δ from the centre's height towards the large end.
///
/// So the centre line stands r0·(1/cos δ − 1) further out than a cylinder's
/// (the rack's reference line where the profile shift puts it, the tooth as
/// thick as drawn); and it must run along the cone ra0·sin δ beyond the
/// small-end face for the hob to finish that face (where it held X at the
/// face, the hob cut the small end as a cylinder of the face's depth).
/// Returns (the lift r0·(1/cos δ − 1), the overtravel ra0·sin δ), mm.
pub fn cone_offsets(angle_deg: f64, hob: HobRadii) -> (f64, f64) {
    let d = angle_deg.to_radians();
    (
        hob.reference_mm * (1.0 / d.cos() - 1.0),
        hob.tip_mm * d.sin(),
    )
}

/// Conical gear: the hob's centre follows the cone line,
/// X(Z) = Xc + lift + (Z − Zl)·slope with Xc the cylinder's finishing X at
/// the large-end face Zl, from that face to the overtravel beyond the small
/// end ([`cone_offsets`]); beyond those, where its envelope no longer
/// touches the face, X holds (further along the line the hob would go
/// towards the table axis, into the arbor of a long small-end cone; and
/// the hob holding X beyond the large end cuts no deeper than at that face,
/// its circle there the nearer one). The path feed along the cone is
/// Vf·√(1 + slope²) so that the axial feed rate stays Vf.
pub fn conical(f: &CutFrame, angle_deg: f64, large_end: LargeEnd, hob: HobRadii) -> CutPath {
    let slope = cone_slope(angle_deg, large_end);
    let (lift, overtravel) = cone_offsets(angle_deg, hob);
    let (z_large, line) = match large_end {
        LargeEnd::Bottom => (
            f.bottom_face_mm,
            (f.bottom_face_mm, f.top_face_mm() + overtravel),
        ),
        LargeEnd::Top => (
            f.top_face_mm(),
            (f.bottom_face_mm - overtravel, f.top_face_mm()),
        ),
    };
    let x_at = |z: f64| f.xc_mm + lift + (z.clamp(line.0, line.1) - z_large) * slope;
    let (start, end) = f.stroke();
    // The cone line's ends in the order the hob meets them, within the
    // stroke.
    let (lo, hi) = (start.min(end), start.max(end));
    let (line_lo, line_hi) = (line.0.clamp(lo, hi), line.1.clamp(lo, hi));
    let (face_in, face_out) = if f.down {
        (line_hi, line_lo)
    } else {
        (line_lo, line_hi)
    };
    let c = p(x_at(start), start);
    let d = p(x_at(end), end);
    let path_feed = f.axial_feed_mm_min * (1.0 + slope * slope).sqrt();
    let mut moves = vec![infeed(
        f,
        c.x_mm,
        "B -> C: INFEED TO THE CONE LINE'S DEPTH AT ITS ENTRY END",
    )];
    // A move of no length is left out (the cone line may start or end at
    // the stroke's end).
    if face_in != start {
        moves.push(mv(
            MoveKind::Feed,
            None,
            Some(face_in),
            f.axial_feed_mm_min,
            "C -> CONE: AXIAL FEED",
        ));
    }
    moves.push(mv(
        MoveKind::Feed,
        Some(x_at(face_out)),
        Some(face_out),
        path_feed,
        "ALONG THE CONE: X FOLLOWS Z OVER THE FACE AND BEYOND ITS SMALL END",
    ));
    if face_out != end {
        moves.push(mv(
            MoveKind::Feed,
            None,
            Some(d.z_mm),
            f.axial_feed_mm_min,
            "CONE -> D: AXIAL FEED",
        ));
    }
    moves.push(retract(f, d));
    CutPath {
        positions: positions(f, c, d),
        moves,
    }
}

/// Radius of a circular crowning through the face ends and the middle,
/// Rc = (b²/4 + Cb²) / (2·Cb), mm.
pub fn crowning_radius_mm(face_width_mm: f64, amount_mm: f64) -> f64 {
    (face_width_mm * face_width_mm / 4.0 + amount_mm * amount_mm) / (2.0 * amount_mm)
}

/// Chords of a parabolic crowning X = Xc − Cb·(2(Z − Zm)/b)² for a chord
/// tolerance ε: the curvature is constant (X″ = 8·Cb/b²), so a chord of length
/// b/n deviates at most X″·(b/n)²/8 = Cb/n², and n = ⌈√(Cb/ε)⌉ (at least 2).
pub fn parabolic_chords(amount_mm: f64, tolerance_mm: f64) -> u32 {
    let n = (amount_mm / tolerance_mm).sqrt().ceil();
    if n.is_finite() {
        (n.max(2.0)).min(f64::from(u32::MAX)) as u32
    } else {
        u32::MAX
    }
}

/// Crowned gear: the teeth are thickest in the middle of the face and thinner by
/// the crowning towards both faces, so the hob cuts deeper towards the faces:
/// outside the face width X stays at Xc − Cb; across it X follows the crowning,
/// a circular arc through (Xc − Cb, faces) and (Xc, middle)
/// programmed exactly as one arc through its middle point, or a parabola
/// programmed as `chords` chords. Returns the path and the largest deviation of
/// the programmed path from the curve.
pub fn crowned(f: &CutFrame, shape: CrowningShape, amount_mm: f64, chords: u32) -> (CutPath, f64) {
    let xe = f.xc_mm - amount_mm;
    let (start, end) = f.stroke();
    let (face_in, face_out) = if f.down {
        (f.top_face_mm(), f.bottom_face_mm)
    } else {
        (f.bottom_face_mm, f.top_face_mm())
    };
    let zm = f.bottom_face_mm + f.face_width_mm / 2.0;
    let c = p(xe, start);
    let d = p(xe, end);
    let vf = f.axial_feed_mm_min;
    let mut moves = vec![
        infeed(f, xe, "B -> C: INFEED TO DEPTH AT THE FACE END"),
        mv(
            MoveKind::Feed,
            None,
            Some(face_in),
            vf,
            "C -> FACE: AXIAL FEED",
        ),
    ];
    let mut deviation = 0.0;
    match shape {
        CrowningShape::Circular => {
            let mut arc = mv(
                MoveKind::Arc,
                Some(xe),
                Some(face_out),
                vf,
                "CROWNING: CIRCULAR ARC THROUGH THE MIDDLE",
            );
            arc.via = Some(p(f.xc_mm, zm));
            arc.radius_mm = Some(crowning_radius_mm(f.face_width_mm, amount_mm));
            moves.push(arc);
        }
        CrowningShape::Parabolic => {
            let n = chords.max(2);
            let b = f.face_width_mm;
            for i in 1..=n {
                let z = face_in + (face_out - face_in) * f64::from(i) / f64::from(n);
                let u = 2.0 * (z - zm) / b;
                let x = if i == n {
                    xe
                } else {
                    f.xc_mm - amount_mm * u * u
                };
                moves.push(mv(
                    MoveKind::Feed,
                    Some(x),
                    Some(z),
                    vf,
                    "CROWNING: PARABOLA CHORD",
                ));
            }
            deviation = amount_mm / (f64::from(n) * f64::from(n));
        }
    }
    moves.push(mv(
        MoveKind::Feed,
        None,
        Some(d.z_mm),
        vf,
        "FACE -> D: AXIAL FEED",
    ));
    moves.push(retract(f, d));
    (
        CutPath {
            positions: positions(f, c, d),
            moves,
        },
        deviation,
    )
}

/// Worm wheel infeed data of one cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WormFrame {
    /// Radial or tangential.
    pub infeed: WormInfeed,
    /// Throat plane height, mm.
    pub throat_z_mm: f64,
    /// Dwell at final depth, s.
    pub dwell_s: f64,
    /// Tangential feed rate, mm/min.
    pub tangential_feed_mm_min: f64,
    /// Tangential start and end Y, mm.
    pub y_mm: [f64; 2],
}

/// Worm wheel. Radial: at the throat plane, rapid to just clear of the blank,
/// radial feed to the final centre distance, dwell, rapid out. Tangential:
/// shift the hob to the start, rapid to the final centre distance, feed along
/// the hob axis (Y) to the end, rapid out.
pub fn worm_wheel(f: &CutFrame, w: &WormFrame) -> CutPath {
    let zt = w.throat_z_mm;
    let d = p(f.xc_mm, zt);
    let e = p(f.clear_x_mm, zt);
    let (c, moves) = match w.infeed {
        WormInfeed::Radial => {
            let c = p(f.clear_x_mm, zt);
            let mut dwell = mv(
                MoveKind::Dwell,
                None,
                None,
                0.0,
                "DWELL AT THE FINAL CENTRE DISTANCE",
            );
            dwell.dwell_s = w.dwell_s;
            (
                c,
                vec![
                    infeed(f, c.x_mm, "B -> C: HOB TIP CLEAR OF THE BLANK"),
                    mv(
                        MoveKind::Feed,
                        Some(d.x_mm),
                        None,
                        f.radial_feed_mm_min,
                        "C -> D: RADIAL FEED TO THE CENTRE DISTANCE",
                    ),
                    dwell,
                    mv(MoveKind::Rapid, Some(e.x_mm), None, 0.0, "D -> E: RETRACT"),
                ],
            )
        }
        WormInfeed::Tangential => {
            let c = d;
            let mut to_start = mv(
                MoveKind::Rapid,
                None,
                None,
                0.0,
                "B: HOB SHIFTED TO THE TANGENTIAL START",
            );
            to_start.y_mm = Some(w.y_mm[0]);
            let mut feed = mv(
                MoveKind::Feed,
                None,
                None,
                w.tangential_feed_mm_min,
                "C -> D: TANGENTIAL FEED ALONG THE HOB AXIS",
            );
            feed.y_mm = Some(w.y_mm[1]);
            (
                c,
                vec![
                    to_start,
                    mv(
                        MoveKind::Rapid,
                        Some(c.x_mm),
                        None,
                        0.0,
                        "B -> C: TO THE FINAL CENTRE DISTANCE",
                    ),
                    feed,
                    mv(MoveKind::Rapid, Some(e.x_mm), None, 0.0, "D -> E: RETRACT"),
                ],
            )
        }
    };
    let positions = Positions {
        A: f.home,
        B: p(f.clear_x_mm + f.retract_mm, zt),
        C: c,
        D: d,
        E: e,
    };
    CutPath { positions, moves }
}

/// Machining time of a path from `start`, minutes: every feed and arc move's
/// length over its feed rate, plus dwells. An arc's length is taken from its
/// chord and radius.
pub fn time_min(start: Position, start_y: f64, moves: &[Move]) -> f64 {
    let (mut x, mut z, mut y) = (start.x_mm, start.z_mm, start_y);
    let mut t = 0.0;
    for m in moves {
        let (nx, nz, ny) = (
            m.x_mm.unwrap_or(x),
            m.z_mm.unwrap_or(z),
            m.y_mm.unwrap_or(y),
        );
        let chord = ((nx - x).powi(2) + (nz - z).powi(2) + (ny - y).powi(2)).sqrt();
        match m.kind {
            MoveKind::Feed => t += chord / m.feed_mm_min,
            MoveKind::Arc => {
                let len = match m.radius_mm {
                    Some(r) if r > chord / 2.0 => 2.0 * r * (chord / (2.0 * r)).asin(),
                    _ => chord,
                };
                t += len / m.feed_mm_min;
            }
            MoveKind::Dwell => t += m.dwell_s / 60.0,
            MoveKind::Rapid => {}
        }
        (x, z, y) = (nx, nz, ny);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn frame() -> CutFrame {
        CutFrame {
            home: p(300.0, 350.0),
            xc_mm: 73.75,
            bottom_face_mm: 50.0,
            face_width_mm: 30.0,
            over_top_mm: 24.0,
            over_bottom_mm: 24.0,
            safety_mm: 2.0,
            retract_mm: 100.0,
            exit_mm: 5.0,
            down: true,
            axial_feed_mm_min: 30.0,
            radial_feed_mm_min: 10.0,
            shift_mm: None,
            clear_x_mm: 82.5,
        }
    }

    #[test]
    fn axial_path_is_the_patent_cycle() {
        let path = axial(&frame());
        let q = path.positions;
        assert_eq!((q.C.x_mm, q.C.z_mm), (73.75, 104.0));
        assert_eq!((q.D.x_mm, q.D.z_mm), (73.75, 26.0));
        assert_eq!((q.B.x_mm, q.E.x_mm), (173.75, 78.75));
        // The feed stroke 78 mm at 30 mm/min.
        assert_relative_eq!(
            time_min(q.B, 0.0, &path.moves),
            78.0 / 30.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn radial_axial_plunges_at_the_entry_face() {
        let path = radial_axial(&frame());
        let q = path.positions;
        assert_eq!(q.C.z_mm, 82.0);
        assert_eq!(path.moves[0].x_mm, Some(82.5));
        assert_eq!(path.moves[1].x_mm, Some(73.75));
        // Plunge 8.75 mm at 10 mm/min, then 56 mm at 30 mm/min.
        assert_relative_eq!(
            time_min(q.B, 0.0, &path.moves),
            8.75 / 10.0 + 56.0 / 30.0,
            epsilon = 1e-12
        );
    }

    /// The hob of the conical tests: ra0 35 mm, r0 32.5 mm.
    const HOB: HobRadii = HobRadii {
        tip_mm: 35.0,
        reference_mm: 32.5,
    };

    #[test]
    fn conical_x_follows_z_along_the_cone_and_holds_beyond_the_faces() {
        let f = frame();
        let path = conical(&f, 6.5, LargeEnd::Bottom, HOB);
        let q = path.positions;
        let d = 6.5f64.to_radians();
        let t = d.tan();
        // The centre line stands r0·(1/cos δ − 1) out from the cylinder's
        // and runs ra0·sin δ on beyond the small (top) face; beyond that
        // and below the large (bottom) face X holds.
        let lift = 32.5 * (1.0 / d.cos() - 1.0);
        let over = 35.0 * d.sin();
        assert_relative_eq!(q.C.x_mm, 73.75 + lift - (30.0 + over) * t, epsilon = 1e-12);
        assert_relative_eq!(q.D.x_mm, 73.75 + lift, epsilon = 1e-12);
        assert_eq!(path.moves[1].z_mm, Some(80.0 + over));
        assert_eq!(path.moves[1].x_mm, None);
        let along = &path.moves[2];
        assert_eq!(along.z_mm, Some(50.0));
        assert_relative_eq!(along.x_mm.unwrap(), 73.75 + lift, epsilon = 1e-12);
        // The axial feed rate stays Vf: time = stroke / Vf.
        assert_relative_eq!(
            time_min(q.B, 0.0, &path.moves),
            78.0 / 30.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn a_cone_large_at_the_top_cut_upwards_runs_on_below_its_small_end() {
        let f = CutFrame {
            down: false,
            ..frame()
        };
        let path = conical(&f, 6.5, LargeEnd::Top, HOB);
        let q = path.positions;
        let d = 6.5f64.to_radians();
        let (lift, over) = (32.5 * (1.0 / d.cos() - 1.0), 35.0 * d.sin());
        // Up from below the small (bottom) end: the cone line starts
        // ra0·sin δ below it, X there deeper by that times tan δ.
        assert_relative_eq!(q.C.z_mm, 26.0, epsilon = 1e-12);
        assert_relative_eq!(
            q.C.x_mm,
            73.75 + lift - (30.0 + over) * d.tan(),
            epsilon = 1e-12
        );
        assert_eq!(path.moves[1].z_mm, Some(50.0 - over));
        let along = &path.moves[2];
        assert_eq!(along.z_mm, Some(80.0));
        assert_relative_eq!(along.x_mm.unwrap(), 73.75 + lift, epsilon = 1e-12);
        assert_relative_eq!(q.D.x_mm, 73.75 + lift, epsilon = 1e-12);
        // A stroke shorter than the overtravel: the line starts at C, and
        // no axial move of no length comes before it.
        let short = CutFrame {
            over_bottom_mm: 2.0,
            ..f
        };
        let path = conical(&short, 6.5, LargeEnd::Top, HOB);
        assert_eq!(path.moves[1].z_mm, Some(80.0));
        assert!(path.moves[1].x_mm.is_some());
    }

    #[test]
    fn circular_crowning_is_one_exact_arc() {
        let (path, dev) = crowned(&frame(), CrowningShape::Circular, 0.02, 0);
        assert_eq!(dev, 0.0);
        let arc = path.moves.iter().find(|m| m.kind == MoveKind::Arc).unwrap();
        let r = arc.radius_mm.unwrap();
        // Rc = (30²/4 + 0.02²)/(2·0.02) = 5625.01 mm.
        assert_relative_eq!(r, 5625.01, epsilon = 1e-9);
        // The three points lie on the circle with centre (Xc − Rc, Zm): deeper at the faces.
        let (cx, cz) = (73.75 - r, 65.0);
        for (x, z) in [(73.73f64, 80.0f64), (73.75, 65.0), (73.73, 50.0)] {
            assert_relative_eq!((x - cx).hypot(z - cz), r, epsilon = 1e-9);
        }
        assert_eq!(arc.via, Some(p(73.75, 65.0)));
        assert_eq!((arc.x_mm, arc.z_mm), (Some(73.73), Some(50.0)));
    }

    #[test]
    fn parabolic_crowning_chords_stay_within_the_tolerance() {
        let (amount, tol) = (0.03, 0.0005);
        let n = parabolic_chords(amount, tol);
        assert_eq!(n, 8); // ⌈√60⌉
        let f = frame();
        let (path, dev) = crowned(&f, CrowningShape::Parabolic, amount, n);
        assert!(dev <= tol, "{dev}");
        // Check the real deviation by sampling every chord against the parabola.
        let curve = |z: f64| 73.75 - amount * (2.0 * (z - 65.0) / 30.0).powi(2);
        let mut prev = (73.75 - amount, 80.0);
        let mut worst: f64 = 0.0;
        for m in path.moves.iter().filter(|m| m.note.contains("CHORD")) {
            let next = (m.x_mm.unwrap(), m.z_mm.unwrap());
            for i in 0..=100 {
                let s = f64::from(i) / 100.0;
                let z = prev.1 + (next.1 - prev.1) * s;
                let x = prev.0 + (next.0 - prev.0) * s;
                worst = worst.max((x - curve(z)).abs());
            }
            prev = next;
        }
        assert!(worst <= tol + 1e-12, "{worst}");
        assert_relative_eq!(worst, dev, epsilon = 1e-6);
    }

    #[test]
    fn worm_wheel_radial_feeds_to_the_centre_distance_and_dwells() {
        let w = WormFrame {
            infeed: WormInfeed::Radial,
            throat_z_mm: 65.0,
            dwell_s: 12.0,
            tangential_feed_mm_min: 0.0,
            y_mm: [0.0, 0.0],
        };
        let path = worm_wheel(&frame(), &w);
        let q = path.positions;
        assert_eq!((q.C.x_mm, q.D.x_mm, q.E.x_mm), (82.5, 73.75, 82.5));
        assert!(path
            .moves
            .iter()
            .any(|m| m.kind == MoveKind::Dwell && m.dwell_s == 12.0));
        assert_relative_eq!(
            time_min(q.B, 0.0, &path.moves),
            8.75 / 10.0 + 12.0 / 60.0,
            epsilon = 1e-12
        );
    }

    #[test]
    fn worm_wheel_tangential_feeds_along_y_at_the_centre_distance() {
        let w = WormFrame {
            infeed: WormInfeed::Tangential,
            throat_z_mm: 65.0,
            dwell_s: 0.0,
            tangential_feed_mm_min: 20.0,
            y_mm: [-90.0, 70.0],
        };
        let path = worm_wheel(&frame(), &w);
        assert_eq!(path.positions.C.x_mm, 73.75);
        assert_eq!(path.moves[2].y_mm, Some(70.0));
        assert_relative_eq!(
            time_min(path.positions.B, 0.0, &path.moves),
            160.0 / 20.0,
            epsilon = 1e-12
        );
    }
}
