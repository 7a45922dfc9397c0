//! "No allocation per step" (issue #66): a control step's planning — the search over pushes, about
//! 300 predictions of the model, the way round the object — reuses buffers the planner sized when
//! it was made, so no step allocates, the first included. Counted by the test binary's allocator
//! (`allocations`) on the sandbox's controller pushing mystery boxes to a goal, every step from the
//! first to the goal held, learning online. The learning, the acting half of a step, grows the push
//! and allocates by design: only the planning half is counted.

#![allow(clippy::unwrap_used)]

use std::path::Path;

use nalgebra::Point2;
use pushlab_core::control::{Goal, Phase, PlanWith, PlannerConfig, SandboxControl};
use pushlab_core::geometry::Pose2;
use pushlab_core::learn::OnlineConfig;
use pushlab_core::model_file::ModelFile;
use pushlab_core::sandbox::{Mystery, MysteryObject};

use crate::allocations;

#[test]
fn a_control_steps_planning_allocates_nothing_once_its_buffers_have_grown() {
    let model = ModelFile::load(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/default-model.json"),
    )
    .unwrap()
    .combined;
    for seed in 1..=3 {
        let mystery = Mystery::draw(seed, MysteryObject::Box).unwrap();
        let goal = Goal::at(Pose2 {
            position: Point2::new(0.25, 0.1),
            yaw: 0.4,
        });
        let config = PlannerConfig {
            seed,
            ..PlannerConfig::default()
        };
        let mut run = SandboxControl::new(
            mystery,
            None,
            &model,
            PlanWith::Online,
            OnlineConfig::default(),
            goal,
            config,
        )
        .unwrap();
        let mut allocating = Vec::new();
        let mut acting = 0;
        let mut phases = Vec::new();
        let mut steps = 0;
        while !run.is_done() && steps < 1200 {
            let before = allocations::on_this_thread();
            let decision = run.decide();
            let made = allocations::on_this_thread() - before;
            if made > 0 {
                allocating.push((steps, made));
            }
            phases.push(decision.phase);
            let before = allocations::on_this_thread();
            run.carry_out(decision);
            acting += allocations::on_this_thread() - before;
            steps += 1;
        }
        assert!(
            run.is_done(),
            "seed {seed}: the goal not reached in {steps} steps"
        );
        // The count counts: the acting half grows the push.
        assert!(acting > 0, "seed {seed}: no allocation counted at all");
        phases.dedup();
        assert!(
            [Phase::Moving, Phase::Pushing, Phase::Holding]
                .iter()
                .all(|p| phases.contains(p)),
            "seed {seed}: every phase walked: {phases:?}"
        );
        assert!(
            allocating.is_empty(),
            "seed {seed}: steps that allocated (step, allocations): {allocating:?}"
        );
    }
}
