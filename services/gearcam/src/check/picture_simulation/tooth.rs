//! The tooth sections of the simulation charts: the cut outline of a few
//! teeth of the middle section over the design outline, the difference
//! magnified normal to the design outline.

use super::{label, MARGIN, PAGE_W, TOOTH_PX};
use gearcam_gearmeasure::outline::{ChartData, GearSpec, Geometry};
use std::f64::consts::{PI, TAU};
use svg::node::element::{Group, Polyline};

/// The tooth sections at `top`: three teeth of the middle section's
/// outline `r_mm`, tooth 1 upright between its neighbours, and the height.
pub(super) fn tooth_sections(
    r_mm: &[f64],
    data: &ChartData,
    spec: &GearSpec,
    geo: &Geometry,
    top: f64,
) -> (Group, f64) {
    let z = data.tooth_centre_rad.len();
    let n = r_mm.len();
    let design = DesignTooth::new(spec, geo);
    let centre = data.tooth_centre_rad[0];
    let pitch = TAU / z as f64;
    let window = 1.5 * pitch;
    // The samples in the window, each with the design point nearest it.
    let mut pts: Vec<(f64, f64, f64, f64, f64)> = Vec::new();
    for (i, &r) in r_mm.iter().enumerate() {
        let d = wrap(TAU * i as f64 / n as f64 - centre);
        if d.abs() > window {
            continue;
        }
        let t = data
            .tooth_centre_rad
            .iter()
            .map(|c| wrap(c - centre))
            .fold(f64::NAN, |b, c| {
                if b.is_nan() || (d - c).abs() < (d - b).abs() {
                    c
                } else {
                    b
                }
            });
        let p = (r * d.sin(), r * d.cos());
        let q = if r >= design.r_form {
            let (qx, qy) = design.nearest(rotate(p, -t));
            rotate((qx, qy), t)
        } else {
            p
        };
        pts.push((d, p.0, p.1, q.0, q.1));
    }
    // In order of angle from tooth 1 (the window may straddle θ = 0).
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let pts: Vec<(f64, f64, f64, f64)> = pts
        .into_iter()
        .map(|(_, a, b, c, d)| (a, b, c, d))
        .collect();
    let worst = pts
        .iter()
        .map(|(px, py, qx, qy)| (px - qx).hypot(py - qy))
        .fold(0.0, f64::max);
    let k = magnification(worst, 0.15 * spec.normal_module_mm);
    let magnified: Vec<(f64, f64)> = pts
        .iter()
        .map(|(px, py, qx, qy)| (qx + k * (px - qx), qy + k * (py - qy)))
        .collect();
    let view = ToothView::new(geo, spec, window, top + 45.0);
    let mut g = Group::new()
        .set("class", "tooth-sections")
        .add(label(
            format!(
                "Tooth sections, middle section, tooth 1 upright: the cut outline (blue) over the design outline (grey), differences ×{k} normal to the design outline"
            ),
            MARGIN,
            top + 12.0,
            12.0,
        ))
        .add(label(
            format!(
                "(design teeth centred on the measured ones; below the form diameter {:.2} mm the cut outline unmagnified)",
                geo.form_diameter_mm
            ),
            MARGIN,
            top + 28.0,
            12.0,
        ));
    for j in [z - 1, 0, 1 % z] {
        let t = wrap(data.tooth_centre_rad[j] - centre);
        let outline: Vec<(f64, f64)> = design
            .outline()
            .into_iter()
            .map(|p| view.px(rotate(p, t)))
            .collect();
        g = g.add(
            Polyline::new()
                .set("class", "design")
                .set("points", outline)
                .set("fill", "none")
                .set("stroke", "#888")
                .set("stroke-width", 1.0),
        );
    }
    g = g.add(
        Polyline::new()
            .set("class", "cut")
            .set(
                "points",
                magnified
                    .into_iter()
                    .map(|p| view.px(p))
                    .collect::<Vec<_>>(),
            )
            .set("fill", "none")
            .set("stroke", "#08519c")
            .set("stroke-width", 1.0),
    );
    (g, view.height_px + 70.0)
}

/// An angle wrapped to (−π, π].
pub(crate) fn wrap(a: f64) -> f64 {
    a - TAU * ((a + PI) / TAU).floor()
}

/// `p` turned by `a` clockwise in the tooth view (x = r·sin, y = r·cos).
fn rotate(p: (f64, f64), a: f64) -> (f64, f64) {
    let (s, c) = a.sin_cos();
    (p.0 * c + p.1 * s, -p.0 * s + p.1 * c)
}

/// The magnification that shows `worst` (mm) as at most `room` (mm): the
/// largest of 1, 2, 5 times a power of ten up to 1000 that does (1 at the
/// least).
pub(crate) fn magnification(worst: f64, room: f64) -> f64 {
    let mut best = 1.0;
    for decade in [1.0, 10.0, 100.0, 1000.0] {
        for f in [1.0, 2.0, 5.0] {
            let k = f * decade;
            if k <= 1000.0 && worst * k <= room {
                best = k;
            }
        }
    }
    best
}

/// The design tooth upright at the origin (x = r·sin, y = r·cos about the
/// gear's axis): involute flanks from the form circle to the tip form
/// circle and the tip arc.
///
/// A right flank (facing +θ) at radius ρ stands at ψ(ρ) = ψb − inv α(ρ)
/// from the tooth's centre, cos α(ρ) = rb/ρ, the left flank at −ψ(ρ):
/// ψb = st/(2r) + inv αt is the half angle of the tooth on the base
/// circle, st = sn/cos β the transverse thickness at the reference radius
/// r, inv αt its involute function (cos αt = rb/r).
pub(crate) struct DesignTooth {
    pub(crate) rb: f64,
    pub(crate) psi_b: f64,
    pub(crate) r_form: f64,
    pub(crate) r_tip: f64,
    points: Vec<(f64, f64)>,
}

impl DesignTooth {
    pub(crate) fn new(spec: &GearSpec, geo: &Geometry) -> DesignTooth {
        let r = geo.reference_diameter_mm / 2.0;
        let rb = geo.base_diameter_mm / 2.0;
        let at = (rb / r).acos();
        let st = geo.design_thickness_mm / spec.helix_deg.to_radians().cos();
        let psi_b = st / (2.0 * r) + (at.tan() - at);
        let (r_form, r_tip) = (
            (geo.form_diameter_mm / 2.0).max(rb),
            geo.tip_form_diameter_mm / 2.0,
        );
        let mut t = DesignTooth {
            rb,
            psi_b,
            r_form,
            r_tip,
            points: Vec::new(),
        };
        t.points = t.build();
        t
    }

    /// ψ(ρ), rad.
    pub(crate) fn psi(&self, rho: f64) -> f64 {
        let a = (self.rb / rho).min(1.0).acos();
        self.psi_b - (a.tan() - a)
    }

    fn build(&self) -> Vec<(f64, f64)> {
        const K: usize = 60;
        let rho = |k: usize| self.r_form + (self.r_tip - self.r_form) * k as f64 / K as f64;
        let polar = |r: f64, a: f64| (r * a.sin(), r * a.cos());
        let mut v: Vec<(f64, f64)> = (0..=K).map(|k| polar(rho(k), -self.psi(rho(k)))).collect();
        let tip = self.psi(self.r_tip);
        v.extend((1..20).map(|k| polar(self.r_tip, -tip + 2.0 * tip * k as f64 / 20.0)));
        v.extend((0..=K).rev().map(|k| polar(rho(k), self.psi(rho(k)))));
        v
    }

    /// The outline as a polyline, left flank up, tip, right flank down.
    pub(crate) fn outline(&self) -> Vec<(f64, f64)> {
        self.points.clone()
    }

    /// The point of the outline nearest `p`.
    pub(crate) fn nearest(&self, p: (f64, f64)) -> (f64, f64) {
        let mut best = (f64::INFINITY, p);
        for w in self.points.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy).max(1e-30))
                .clamp(0.0, 1.0);
            let q = (a.0 + t * dx, a.1 + t * dy);
            let d = (q.0 - p.0).hypot(q.1 - p.1);
            if d < best.0 {
                best = (d, q);
            }
        }
        best.1
    }
}

/// The tooth view's placement: mm to px.
struct ToothView {
    scale: f64,
    x_mid: f64,
    y_top_mm: f64,
    top: f64,
    /// The height the view takes, px.
    height_px: f64,
}

impl ToothView {
    fn new(geo: &Geometry, spec: &GearSpec, window: f64, top: f64) -> ToothView {
        let ra = geo.tip_form_diameter_mm / 2.0 + 0.3 * spec.normal_module_mm;
        let rf = spec.root_diameter_mm / 2.0 - 0.3 * spec.normal_module_mm;
        let width = 2.0 * ra * window.sin();
        let height = ra - rf * window.cos();
        let scale = ((PAGE_W - 2.0 * MARGIN) / width).min(TOOTH_PX / height);
        ToothView {
            scale,
            x_mid: PAGE_W / 2.0,
            y_top_mm: ra,
            top,
            height_px: height * scale,
        }
    }

    fn px(&self, p: (f64, f64)) -> (f64, f64) {
        (
            self.x_mid + p.0 * self.scale,
            self.top + (self.y_top_mm - p.1) * self.scale,
        )
    }
}
