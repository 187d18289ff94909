//! Via-points reached: each move's end reports the CoM via-point of the motion file
//! (`com_target`), the CoM of the IK's path there (`com_reached`, checked here against the
//! model's CoM at the nearest IK sample) and their distance; link moves report their distance
//! and angle to their via-points; `checks.max_via_point_error` is the largest of them. Landings
//! (held as equalities by the IK) end within 1 mm and 0.5 degree. The small humanoid needs no
//! Python.

use stance::motion::result::MotionStatus;
use stance::motion::{experiments, run_full, RunOptions};
use stance::stance_robot::{center_of_mass, Data};

#[test]
fn every_move_reports_its_via_points_and_where_the_path_was() {
    let spec = experiments::by_name("small-sway").unwrap();
    let run = run_full(spec.clone(), &RunOptions::default()).unwrap();
    let r = &run.result;
    assert_eq!(r.status, MotionStatus::Optimal, "{:?}", r.failure);
    let m = &run.plan.robot.model;
    let mut data = Data::new(m);
    // the file's CoM via-points: the initial CoM moved by each move's `com.by`
    let c0 = center_of_mass(m, &mut data, &run.paths[0].samples[0].q).unwrap();
    let mut target = [c0.x, c0.y, c0.z];
    let mut worst = 0.0f64;
    for ((seg, info), path) in spec.segments.iter().zip(&r.segments).zip(&run.paths) {
        assert_eq!(info.moves.len(), seg.moves.len());
        for (mv, out) in seg.moves.iter().zip(&info.moves) {
            if let Some(stance::motion::spec::ComTarget::By(v)) = &mv.com {
                for (t, d) in target.iter_mut().zip(v) {
                    *t += d;
                }
            }
            for (a, b) in out.com_target.iter().zip(&target) {
                assert!((a - b).abs() <= 1e-12, "{out:?}");
            }
            // the model's CoM at the IK sample nearest the move's end, which is at most half
            // a step away (the CoM moves less than its path rate times that)
            let reached = out.com_reached.unwrap();
            let (i, smp) = path
                .samples
                .iter()
                .enumerate()
                .min_by(|a, b| {
                    (a.1.s - out.s_end)
                        .abs()
                        .total_cmp(&(b.1.s - out.s_end).abs())
                })
                .unwrap();
            let c = center_of_mass(m, &mut data, &smp.q).unwrap();
            let slack = path.samples[i].terms.p_s.norm() * (smp.s - out.s_end).abs() + 1e-9;
            let d = ((c.x - reached[0]).powi(2)
                + (c.y - reached[1]).powi(2)
                + (c.z - reached[2]).powi(2))
            .sqrt();
            assert!(d <= slack, "{d} > {slack}");
            let e = out.com_error.unwrap();
            let dist = (0..3)
                .map(|j| (reached[j] - target[j]).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!((e - dist).abs() <= 1e-15);
            worst = worst.max(e);
            for l in &out.links {
                worst = worst.max(l.position_error);
            }
        }
    }
    let c = r.checks.as_ref().unwrap();
    assert_eq!(c.max_via_point_error, worst);
    // the landing foot's move ends on its via-point (a hard task)
    let landing = r.segments[1].moves.last().unwrap();
    assert_eq!(landing.links.len(), 1);
    assert_eq!(landing.links[0].surface, "RF");
    assert!(landing.links[0].position_error <= 1e-3);
    assert!(landing.links[0].rotation_error_deg <= 0.5);
    eprintln!(
        "small-sway: via-points within {:.2} mm (CoM), landing {:.4} mm",
        worst * 1e3,
        landing.links[0].position_error * 1e3
    );
}
