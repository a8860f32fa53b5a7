//! A section cut only within angular windows (`cut::Wanted::Within`) has,
//! inside them, the outline the cut all round gives: the steps of a pass
//! the windowed cut leaves untraced are shown to change nothing there. And
//! the windowed cut does leave work out: outside the windows its outline
//! stands higher.

mod common;

use gearcam_hobsim::cut::{self, Blank, Resolution, Wanted};
use gearcam_hobsim::hob::{Hob, HobExtras};
use gearcam_hobsim::kinematics::{self, MachineErrors, MachineRates, Timeline};

const TAU: f64 = std::f64::consts::TAU;

/// Program `name`'s timeline on a machine with `errors`, its hob and an
/// uncut blank of 3 sections.
fn setup(name: &str, errors: MachineErrors) -> (Timeline, Hob, Blank) {
    let (text, model) = common::program(name);
    let (check, trace) = gearcam_nc::check(&text, &model);
    assert!(check.ok, "{:?}", check.findings);
    let tl = kinematics::from_trace_with(&trace, &model, MachineRates::default(), errors)
        .expect("timeline");
    let hob = Hob::from_data(&model.plan.hob, HobExtras::default()).expect("hob");
    let g = &model.plan.gear;
    let h = g.fixture_height_mm;
    let z = Blank::planes(h + 1.0, h + g.face_width_mm - 1.0, 3);
    let r = model.model.blank_od_mm / 2.0;
    (tl, hob, Blank::new(z, r, 4096).expect("blank"))
}

/// Windows of every width from a tenth of a tooth to three teeth, one
/// across θ = 0, different in each section.
fn windows(teeth: u32) -> Vec<Wanted> {
    let pitch = TAU / f64::from(teeth);
    vec![
        Wanted::Within(vec![(-0.2 * pitch, 0.3 * pitch), (2.0, 2.0 + 3.0 * pitch)]),
        Wanted::Within(vec![
            (1.0, 1.0 + 0.1 * pitch),
            (4.0 + TAU, 4.0 + TAU + pitch),
        ]),
        Wanted::Within(vec![(3.0, 3.0 + 1.5 * pitch)]),
    ]
}

fn inside(wanted: &Wanted, theta: f64) -> bool {
    match wanted {
        Wanted::Everywhere => true,
        Wanted::Within(w) => w.iter().any(|&(a, b)| {
            let d = (theta - a).rem_euclid(TAU);
            d <= b - a
        }),
    }
}

/// The largest difference of the windowed outline from the whole one
/// within the windows, and how many rays outside them stand higher.
fn compare(name: &str, errors: MachineErrors, exhaustive: bool) -> (f64, usize) {
    let (tl, hob, fresh) = setup(name, errors);
    let (_, model) = common::program(name);
    let wanted = windows(model.plan.gear.teeth);
    let res = Resolution::coarse();
    let (mut whole, mut part) = (fresh.clone(), fresh);
    if exhaustive {
        cut::cut_exhaustive(&tl, &hob, &mut whole, res).expect("cut");
        cut::cut_exhaustive_within(&tl, &hob, &mut part, res, &wanted).expect("cut");
    } else {
        cut::cut(&tl, &hob, &mut whole, res).expect("cut");
        let all = vec![true; tl.segments().len()];
        cut::cut_segments(&tl, &hob, &mut part, res, &all, (&wanted, 2)).expect("cut");
    }
    let (mut worst, mut higher) = (0.0f64, 0);
    for (j, w) in wanted.iter().enumerate() {
        for (i, (a, b)) in whole.r_mm[j].iter().zip(&part.r_mm[j]).enumerate() {
            if inside(w, whole.theta(i)) {
                worst = worst.max((a - b).abs());
            } else if b > &(a + 1e-6) {
                higher += 1;
            }
        }
    }
    (worst, higher)
}

#[test]
#[ignore = "about 10 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn within_its_windows_a_section_is_cut_as_all_round() {
    let runout = MachineErrors {
        hob_radial_mm: 0.2,
        hob_radial_phase_deg: 40.0,
        hob_axial_mm: 0.1,
        table_mm: 0.2,
        table_phase_deg: 200.0,
        centre_distance_mm: -0.02,
        swivel_deg: 0.1,
        ..Default::default()
    };
    for (name, errors) in [
        ("spur_840d", MachineErrors::default()),
        ("helical_climb_840d", MachineErrors::default()),
        ("helical_climb_840d", runout),
    ] {
        let (worst, higher) = compare(name, errors, false);
        assert!(
            worst < 1e-9,
            "{name}: within the windows the outlines differ by {worst:.2e} mm"
        );
        assert!(
            higher > 1000,
            "{name}: only {higher} rays left uncut outside the windows"
        );
    }
}

#[test]
#[ignore = "about 30 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn within_its_windows_every_piece_refined_is_cut_as_all_round() {
    let (worst, higher) = compare("spur_840d", MachineErrors::default(), true);
    assert!(
        worst < 1e-9,
        "within the windows the outlines differ by {worst:.2e} mm"
    );
    assert!(
        higher > 1000,
        "only {higher} rays left uncut outside the windows"
    );
}

#[test]
#[ignore = "about 10 s in release: cargo test --release -p gearcam-hobsim -- --ignored"]
fn a_section_shared_among_threads_is_the_section_cut_by_one() {
    let (tl, hob, fresh) = setup("helical_climb_840d", MachineErrors::default());
    let res = Resolution::coarse();
    let (mut one, mut shared) = (fresh.clone(), fresh);
    let all = vec![true; tl.segments().len()];
    let wanted = vec![
        Wanted::Everywhere,
        Wanted::Within(vec![]),
        Wanted::Within(vec![]),
    ];
    cut::cut_segments(&tl, &hob, &mut one, res, &all, (&wanted, 1)).expect("cut");
    // Three threads and one section all round: it is cut as three windows.
    cut::cut_segments(&tl, &hob, &mut shared, res, &all, (&wanted, 3)).expect("cut");
    let d = one.r_mm[0]
        .iter()
        .zip(&shared.r_mm[0])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(d < 1e-9, "the outlines differ by {d:.2e} mm");
    let uncut = one.outer_radius_mm;
    for j in [1, 2] {
        assert!(one.r_mm[j]
            .iter()
            .chain(&shared.r_mm[j])
            .all(|&r| r == uncut));
    }
}

#[test]
fn a_window_turned_back_or_not_a_number_is_refused() {
    let (tl, hob, mut blank) = setup("spur_840d", MachineErrors::default());
    let all = vec![true; tl.segments().len()];
    for w in [(1.0, 0.5), (f64::NAN, 1.0)] {
        let wanted = vec![
            Wanted::Everywhere,
            Wanted::Within(vec![w]),
            Wanted::Everywhere,
        ];
        let err = cut::cut_segments(
            &tl,
            &hob,
            &mut blank,
            Resolution::coarse(),
            &all,
            (&wanted, 1),
        )
        .unwrap_err()
        .to_string();
        assert!(err.contains("wanted") && err.contains("from ≤ to"), "{err}");
    }
}
