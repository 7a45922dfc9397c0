//! The tables `pushlab eval` prints: the paper-style rows, the physics-only rows, each push, the
//! per-label means and how well the COM was found. The numbers are the report's; this only lays
//! them out.

use pushlab_core::experiment::report::EvalReport;
use pushlab_core::experiment::{self, BestFitSummary, ComSummary, Evaluation, UsedRecording};
use pushlab_core::learn::Nmse;

/// Prints the paper-style table, the physics rows, the per-trajectory results and per-label means.
pub fn print_tables(report: &EvalReport, evaluation: &Evaluation, online: &[UsedRecording]) {
    println!();
    println!(
        "{:<18} {:>9} {:>9}   data ({} model)",
        "NMSE", "pos", "rot", report.config.kind
    );
    // Rows without a value (no offline data, no pure network) are left out; eval said why once.
    let row = |name: &str, n: Option<&Nmse>, data: &str| {
        if let Some(n) = n {
            println!("{name:<18} {:>9.3} {:>9.3}   {data}", n.pos, n.rot);
        }
    };
    row("Offline NN", report.offline_nn.as_ref(), "offline");
    row("Offline", report.offline.as_ref(), "offline");
    row(
        "Online NN",
        report.online_nn.as_ref(),
        "online (network alone)",
    );
    row("Fixed", Some(&report.fixed), "online");
    row("Online", Some(&report.online), "online");
    if let Some(p) = &report.physics {
        row(
            "Physics offline",
            p.offline.as_ref(),
            "offline (physics only, no network)",
        );
        row(
            "Physics fixed",
            Some(&p.fixed),
            "online (physics only, no network)",
        );
        row(
            "Physics online",
            Some(&p.online),
            "online (physics only, no network)",
        );
        row(
            "Weighted",
            p.weighted.as_ref(),
            "online (combined and physics only, weighed online)",
        );
    }
    println!();
    // With --physics, each push's physics-only online NMSE beside the combined model's.
    let physics_online = |recording: usize| {
        let push = (evaluation.physics_pushes.iter()).find(|p| p.recording == recording);
        match (report.physics.is_some(), push) {
            (false, _) => String::new(),
            (true, Some(p)) => {
                let weighted = p.weighted.map_or_else(
                    || format!(" {:>15}", "-"),
                    |w| format!(" {:>7.3}/{:<7.3}", w.pos, w.rot),
                );
                format!(" {:>7.3}/{:<7.3}{weighted}", p.online.pos, p.online.rot)
            }
            (true, None) => format!(" {:>15} {:>15}", "-", "-"),
        }
    };
    // With --best-fit, each push's best θ's NMSE beside them: what no online learner beats.
    let best = |r: &experiment::TrajectoryRun| match (report.best_fit.is_some(), r.best_fit) {
        (false, _) => String::new(),
        (true, Some(b)) => format!(" {:>7.3}/{:<7.3}", b.nmse.pos, b.nmse.rot),
        (true, None) => format!(" {:>15}", "-"),
    };
    println!(
        "{:<28} {:>5} {:>15} {:>15}{}{} {:>27} {:>15}",
        "online trajectory",
        "steps",
        "fixed pos/rot",
        "online pos/rot",
        if report.physics.is_some() {
            format!(" {:>15} {:>15}", "phys online", "weighted")
        } else {
            String::new()
        },
        if report.best_fit.is_some() {
            format!(" {:>15}", "best θ")
        } else {
            String::new()
        },
        "COM offset learned (true)",
        "h learned (true)"
    );
    for (t, r) in report.trajectories.iter().zip(&evaluation.trajectories) {
        let recording = &online[r.recording].recording;
        let name = format!("{}/{}", recording.setting.name, recording.name);
        let com_true = t
            .com_offset_true
            .map(|c| format!("({:.3},{:.3})", c[0], c[1]))
            .unwrap_or_else(|| "?".into());
        let h_true = t
            .h_true
            .map(|h| format!("{h:.3}"))
            .unwrap_or_else(|| "?".into());
        println!(
            "{name:<28} {:>5} {:>7.3}/{:<7.3} {:>7.3}/{:<7.3}{}{} {:>13} {:<13} {:>6.3} {:<8}",
            t.steps,
            t.fixed.pos,
            t.fixed.rot,
            t.online.pos,
            t.online.rot,
            physics_online(r.recording),
            best(r),
            format!(
                "({:.3},{:.3})",
                t.com_offset_learned[0], t.com_offset_learned[1]
            ),
            com_true,
            t.h_learned,
            format!("({h_true})"),
        );
    }
    if report.config.carry_theta {
        let continued = report.trajectories.iter().filter(|t| t.continued).count();
        println!(
            "--carry-theta: {continued} of {} trajectories went on from the one before them (same \
             object); the others started from θ_online(0)",
            report.trajectories.len()
        );
    }
    if let Some([x, y]) = report.config.start_com_shift {
        println!(
            "--start-com-shift: pushes not carried on started believing the COM ({:.1}, {:.1}) mm \
             from θ_online(0)'s (kept inside the object), the prior centred there",
            x * 1e3,
            y * 1e3
        );
    }
    if let Some(p) = &report.per_label {
        println!();
        println!(
            "{:<18} {:>8} {:>11} {:>11}",
            "mean loss by label", "frames", "fixed", "online"
        );
        for (f, o) in p.fixed.iter().zip(&p.online) {
            println!(
                "{:<18} {:>8} {:>11.3} {:>11.3}",
                f.label, f.count, f.mean, o.mean
            );
        }
    }
    if let Some(c) = &report.com_found {
        println!();
        println!("{}", com_found_line(c));
    }
    if let Some(c) = &report.physics_com_found {
        println!("Physics-only online: {}", com_found_line(c));
    }
    if let Some(b) = &report.best_fit {
        println!(
            "{}",
            best_fit_line(
                "Best θ per push",
                b,
                &report.online,
                report.com_found.as_ref()
            )
        );
    }
    if let Some(b) = &report.object_best_fit {
        let com = b.mean_com_error_m.map(|e| {
            format!(
                "; mean COM error {:.1} mm over {} objects with a known COM",
                e * 1e3,
                b.with_truth
            )
        });
        println!(
            "Best θ per object (all its carried pushes at once, held fixed): NMSE {:.3}/{:.3} pos/rot \
             over {} objects{}",
            b.nmse.pos,
            b.nmse.rot,
            b.pushes,
            com.unwrap_or_default()
        );
    }
    if let (Some(b), Some(p)) = (&report.physics_best_fit, &report.physics) {
        let found = report.physics_com_found.as_ref();
        println!(
            "{}",
            best_fit_line("Physics-only best θ per push", b, &p.online, found)
        );
    }
    for s in &evaluation.left_out {
        println!("left out: {}", s.message());
    }
    println!();
}

/// One line on each push's best θ against what online learning reached (`online`, `found`).
fn best_fit_line(
    what: &str,
    b: &BestFitSummary,
    online: &Nmse,
    found: Option<&ComSummary>,
) -> String {
    let com = match (b.mean_com_error_m, found) {
        (Some(best), Some(c)) => format!(
            "; mean COM error {:.1} mm over {} pushes with a known COM (online learning: {:.1} mm)",
            best * 1e3,
            b.with_truth,
            c.mean_error_m * 1e3
        ),
        (Some(best), None) => format!(
            "; mean COM error {:.1} mm over {} pushes with a known COM",
            best * 1e3,
            b.with_truth
        ),
        _ => String::new(),
    };
    format!(
        "{what} (the whole push at once, held fixed): NMSE {:.3}/{:.3} pos/rot over {} pushes \
         (online {:.3}/{:.3}){com}",
        b.nmse.pos, b.nmse.rot, b.pushes, online.pos, online.rot
    )
}

/// One line on how well online learning found a known COM.
fn com_found_line(c: &ComSummary) -> String {
    let settled = match c.median_frames_to_near {
        Some(frames) => format!("after a median {frames} frames"),
        None => "never".into(),
    };
    format!(
        "COM found on {} pushes with a known COM: the 95 % ellipse holds it on {} ({:.0} %); \
         mean final error {:.1} mm; within 5 mm to the end on {} ({settled})",
        c.pushes,
        c.within_95,
        100.0 * c.coverage(),
        c.mean_error_m * 1e3,
        c.settled,
    )
}
