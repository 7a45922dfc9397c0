//! eval's JSON report, its figure and the best fits it finds.

use super::*;

#[test]
fn eval_writes_the_documented_json_and_a_png_and_skips_a_broken_file() {
    let dir = temp_dir("eval");
    let broken = dir.join("motion_surface=abs_shape=rect1_broken.json");
    std::fs::write(&broken, "{ this is not json").unwrap();
    let json = dir.join("out.json");
    let png = dir.join("out.png");
    let offline = offline_subset();
    let mut online = online_subset();
    online.push(broken.display().to_string());
    let (json_s, png_s) = (json.display().to_string(), png.display().to_string());
    let args = eval_args(
        &offline,
        &online,
        &[
            "--epochs",
            "3",
            "--seed",
            "7",
            "--horizon",
            "5",
            "--steps",
            "4",
            "--lr",
            "0.01",
            "--physics",
            "--best-fit",
            "--json",
            &json_s,
            "--plot",
            &png_s,
        ],
    );
    let run = pushlab(&args);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);

    // The files used and the broken one, by name with its reason.
    assert!(
        run.stdout.contains("offline: 6 recording(s)"),
        "{}",
        run.stdout
    );
    assert!(
        run.stdout.contains("online: 2 recording(s)"),
        "{}",
        run.stdout
    );
    assert!(run.stdout.contains("offline_020.csv"), "{}", run.stdout);
    let skipped_line = run
        .stdout
        .lines()
        .find(|l| l.contains("skipped:"))
        .expect("a skipped line");
    assert!(skipped_line.contains("rect1_broken.json"), "{skipped_line}");
    // The table rows.
    for row in [
        "Offline NN",
        "Offline ",
        "Fixed ",
        "Online ",
        "Physics fixed",
        "Physics online",
        "Weighted",
    ] {
        assert!(
            run.stdout.lines().any(|l| l.starts_with(row)),
            "no row {row:?}:\n{}",
            run.stdout
        );
    }

    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in ["offline_nn", "offline", "fixed", "online"] {
        nmse(&report[key], key);
    }
    let config = &report["config"];
    assert_eq!(config["horizon"], 5);
    assert_eq!(config["epochs"], 3);
    assert_eq!(config["seed"], 7);
    assert_eq!(config["steps"], 4);
    assert_eq!(config["lr"], 0.01);
    assert_eq!(config["model"], Value::Null);
    assert_eq!(config["offline_sources"].as_array().unwrap().len(), 6);
    let trajectories = report["trajectories"].as_array().unwrap();
    assert_eq!(trajectories.len(), 2);
    for (t, source) in trajectories.iter().zip(online_subset()) {
        assert_eq!(t["source"].as_str().unwrap(), source);
        // 100 frames at horizon 5 give 95 steps (the sample data has 10 s at 10 Hz plus one frame).
        let steps = t["steps"].as_u64().unwrap();
        assert!((90..=100).contains(&steps), "steps {steps}");
        nmse(&t["fixed"], "fixed");
        nmse(&t["online"], "online");
        let learned = t["com_offset_learned"].as_array().unwrap();
        assert_eq!(learned.len(), 2);
        for c in learned {
            let c = c.as_f64().unwrap();
            assert!(
                c.abs() < 0.3,
                "learned COM offset {c} is outside a 0.3 × 0.4 m box"
            );
        }
        let h = t["h_learned"].as_f64().unwrap();
        assert!((0.001..=2.0).contains(&h), "h {h}");
        assert_eq!(t["com_offset_true"], serde_json::json!([0.05, 0.05]));
        let h_true = t["h_true"].as_f64().unwrap();
        assert!(h_true > 0.05 && h_true < 0.3, "h_true {h_true}");
    }
    for key in ["offline", "fixed", "online", "weighted"] {
        nmse(&report["physics"][key], key);
    }
    // The physics-only model's COM on the same pushes, its error against the same truth, and the
    // line that sets it beside the combined model's.
    let physics = report["physics_trajectories"].as_array().unwrap();
    assert_eq!(physics.len(), 2);
    for (p, source) in physics.iter().zip(online_subset()) {
        assert_eq!(p["source"].as_str().unwrap(), source);
        let learned: Vec<f64> = (p["com_offset_learned"].as_array().unwrap().iter())
            .map(|c| c.as_f64().unwrap())
            .collect();
        let error = p["com_found"]["error_m"].as_f64().unwrap();
        let distance = (learned[0] - 0.05).hypot(learned[1] - 0.05);
        assert!(
            (error - distance).abs() < 1e-12,
            "{error} against {distance}"
        );
        // Learning moved it from the geometric centre (θ_online(0)) toward the true COM.
        assert!(
            error < 0.05_f64.hypot(0.05),
            "physics-only COM error {error} m"
        );
    }
    // Each push ends with weights of the combined model between 0 and 1, moved from the prior.
    for p in physics {
        for part in ["pos", "rot"] {
            let w = p["weight_end"][part].as_f64().unwrap();
            let prior = pushlab_core::learn::WeightConfig::default().prior;
            assert!(w > 0.0 && w < 1.0 && w != prior, "{part} weight {w}");
        }
    }
    // Each push's physics-only and weighted NMSE: the report's row is their mean weighted by the
    // push's samples (the same frames as the combined model's), and the table prints it beside the
    // combined model's.
    for key in ["fixed", "online", "weighted"] {
        let (mut sum_pos, mut sum_rot, mut samples) = (0.0, 0.0, 0.0);
        for (p, t) in physics.iter().zip(trajectories) {
            nmse(&p[key], key);
            let steps = t["steps"].as_f64().unwrap();
            sum_pos += steps * p[key]["pos"].as_f64().unwrap();
            sum_rot += steps * p[key]["rot"].as_f64().unwrap();
            samples += steps;
        }
        let row = &report["physics"][key];
        for (mean, axis) in [(sum_pos / samples, "pos"), (sum_rot / samples, "rot")] {
            let expected = row[axis].as_f64().unwrap();
            assert!(
                (mean - expected).abs() <= 1e-12 * expected.abs(),
                "physics {key} {axis}: {mean} from the pushes, {expected} in the row"
            );
        }
    }
    let header = (run.stdout.lines())
        .find(|l| l.starts_with("online trajectory"))
        .unwrap();
    assert!(
        header.contains("online pos/rot     phys online        weighted"),
        "{header}"
    );
    let first = physics[0]["online"]["pos"].as_f64().unwrap();
    assert!(
        (run.stdout.lines()).any(|l| l.contains(&format!(
            "/{:<7.3} {first:>7.3}/",
            trajectories[0]["online"]["rot"].as_f64().unwrap()
        ))),
        "{}",
        run.stdout
    );
    assert_eq!(report["physics_com_found"]["pushes"], 2);
    assert!(
        run.stdout
            .lines()
            .any(|l| l.starts_with("Physics-only online: COM found on 2 pushes")),
        "{}",
        run.stdout
    );
    // --best-fit: each push's best θ for both models fits the whole push at least as well as
    // θ_online(0) (the fixed run), its COM error is against the setting's truth, and the summary
    // lines are printed.
    for (t, p) in trajectories.iter().zip(physics) {
        for (kind, push) in [("combined", t), ("physics", p)] {
            let fit = &push["best_fit"];
            assert_eq!(fit["samples"], t["steps"], "{kind}: {fit}");
            let fixed = 2.0 * push["fixed"]["pos"].as_f64().unwrap()
                + push["fixed"]["rot"].as_f64().unwrap();
            let best = fit["mean_loss"].as_f64().unwrap();
            assert!(best <= fixed + 1e-12, "{kind}: best {best} > fixed {fixed}");
            let total =
                2.0 * fit["nmse"]["pos"].as_f64().unwrap() + fit["nmse"]["rot"].as_f64().unwrap();
            assert!(
                (total - best).abs() < 1e-9 * best.max(1.0),
                "{kind}: {total} vs {best}"
            );
            let (com, truth) = (&fit["theta"]["com_offset"], &t["com_offset_true"]);
            let error = (com[0].as_f64().unwrap() - truth[0].as_f64().unwrap())
                .hypot(com[1].as_f64().unwrap() - truth[1].as_f64().unwrap());
            let reported = fit["com_error_m"].as_f64().unwrap();
            assert!((reported - error).abs() < 1e-12, "{kind}: {fit}");
        }
    }
    // The trajectory table gives each push's best NMSE in a "best θ" column after "phys online"
    // and "weighted".
    let header = (run.stdout.lines())
        .find(|l| l.starts_with("online trajectory"))
        .unwrap();
    assert!(
        header.contains("phys online        weighted          best θ"),
        "{header}"
    );
    let (first, phys) = (&trajectories[0], &physics[0]);
    let cells = format!(
        "{:>7.3}/{:<7.3} {:>7.3}/{:<7.3} {:>7.3}/{:<7.3}",
        phys["online"]["pos"].as_f64().unwrap(),
        phys["online"]["rot"].as_f64().unwrap(),
        phys["weighted"]["pos"].as_f64().unwrap(),
        phys["weighted"]["rot"].as_f64().unwrap(),
        first["best_fit"]["nmse"]["pos"].as_f64().unwrap(),
        first["best_fit"]["nmse"]["rot"].as_f64().unwrap(),
    );
    assert!(
        (run.stdout.lines()).any(|l| l.contains(&cells)),
        "{cells}\n{}",
        run.stdout
    );
    assert_eq!(report["best_fit"]["pushes"], 2);
    assert_eq!(report["physics_best_fit"]["pushes"], 2);
    for line in [
        "Best θ per push (the whole push",
        "Physics-only best θ per push",
    ] {
        assert!(
            run.stdout.lines().any(|l| l.starts_with(line)),
            "{line}: {}",
            run.stdout
        );
    }
    let skipped = report["skipped"].as_array().unwrap();
    assert_eq!(skipped.len(), 1, "{skipped:?}");
    assert!(
        skipped[0]["path"]
            .as_str()
            .unwrap()
            .ends_with("rect1_broken.json")
    );

    // The figure: a valid PNG of the documented size, with both curve colours drawn.
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let image = image::load_from_memory(&bytes)
        .expect("decodable PNG")
        .to_rgb8();
    assert_eq!(image.dimensions(), (1000, 400));
    let has = |rgb: [u8; 3]| image.pixels().filter(|p| p.0 == rgb).count();
    assert!(has([31, 119, 180]) > 500, "blue (fixed) curve missing");
    assert!(has([255, 127, 14]) > 500, "orange (online) curve missing");
    assert!(has([0, 0, 0]) > 500, "black offline line and text missing");
}

#[test]
fn best_fit_with_carried_theta_fits_each_object_over_all_its_pushes() {
    let dir = temp_dir("eval-object-best-fit");
    let json = dir.join("out.json");
    let json_s = json.display().to_string();
    let (offline, online) = (offline_subset(), online_subset());
    let eval = |carry: &[&str]| {
        let mut extra = vec![
            "--epochs",
            "3",
            "--horizon",
            "5",
            "--best-fit",
            "--json",
            &json_s,
        ];
        extra.extend_from_slice(carry);
        let run = pushlab(&eval_args(&offline, &online, &extra));
        assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
        let report: Value = serde_json::from_slice(&std::fs::read(&json).unwrap()).unwrap();
        (run, report)
    };
    let (run, report) = eval(&["--carry-theta"]);
    // The two pushes are of one box: one object, both its pushes, every sample of both.
    let objects = report["object_best_fits"].as_array().unwrap();
    assert_eq!(objects.len(), 1, "{objects:?}");
    assert_eq!(objects[0]["sources"], serde_json::json!(online));
    let trajectories = report["trajectories"].as_array().unwrap();
    let steps: u64 = trajectories
        .iter()
        .map(|t| t["steps"].as_u64().unwrap())
        .sum();
    let fit = &objects[0]["best_fit"];
    assert_eq!(fit["samples"].as_u64(), Some(steps));
    // It fits both pushes at least as well as θ_online(0) does (the fixed runs, by samples).
    let fixed: f64 = (trajectories.iter())
        .map(|t| {
            let n = t["steps"].as_f64().unwrap();
            n * (2.0 * t["fixed"]["pos"].as_f64().unwrap() + t["fixed"]["rot"].as_f64().unwrap())
        })
        .sum::<f64>()
        / steps as f64;
    let best = fit["mean_loss"].as_f64().unwrap();
    assert!(best <= fixed + 1e-12, "object best {best} > fixed {fixed}");
    assert_eq!(report["object_best_fit"]["pushes"], 1);
    assert!(
        (run.stdout.lines())
            .any(|l| l.starts_with("Best θ per object (all its carried pushes at once")),
        "{}",
        run.stdout
    );
    // Without --carry-theta there are no objects' fits.
    let (_, report) = eval(&[]);
    assert!(report.get("object_best_fits").is_none(), "{report}");
    std::fs::remove_dir_all(&dir).ok();
}
