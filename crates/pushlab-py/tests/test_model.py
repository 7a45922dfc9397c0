"""pushlab.Model: trained, saved and run online from Python, with pushlab eval's numbers to 1e-12."""

import json

import numpy as np
import pytest

import pushlab
from conftest import SET, run_cli

OFFLINE = sorted(SET.glob("offline_*.csv"))
ONLINE = sorted(SET.glob("online_*.csv"))
# Few epochs: the test compares Python with the CLI on one model, it does not judge the model.
EPOCHS = 4


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    model = pushlab.Model.train(pushlab.load(OFFLINE), epochs=EPOCHS, seed=3, baseline=True)
    assert model.kind == "contact" and model.horizon == 1 and model.has_baseline
    path = tmp_path_factory.mktemp("model") / "model.json"
    model.save(path)
    return path


@pytest.mark.parametrize("optimizer", ["gd", "gauss-newton"])
def test_online_nmse_is_pushlab_evals_per_trajectory(model_file, cli, tmp_path, optimizer):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--optimizer", optimizer,
        "--offline", *map(str, OFFLINE[:3]), "--online", *map(str, ONLINE), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())
    by_file = {t["source"].rsplit("/", 1)[-1]: t for t in report["trajectories"]}
    assert len(by_file) == len(ONLINE)

    model = pushlab.Model.load(model_file)
    for recording in pushlab.load(ONLINE):
        run = model.online(recording, optimizer=optimizer)
        expected = by_file[f"{recording.name}.csv"]
        assert run.steps == expected["steps"] == len(recording) - 1
        for key in ("pos", "rot"):
            assert run.nmse[key] == pytest.approx(expected["online"][key], rel=0, abs=1e-12)
            assert run.fixed_nmse[key] == pytest.approx(expected["fixed"][key], rel=0, abs=1e-12)
        np.testing.assert_allclose(run.theta_end, [*expected["com_offset_learned"], expected["h_learned"]], rtol=0, atol=1e-12)
        np.testing.assert_allclose(run.com_offset_cov, expected["com_offset_cov"], rtol=0, atol=1e-12)
        parts = run.com_sigma_parts
        assert set(parts) == {"frames_m", "misfit_m", "drift_m"}
        for key, value in parts.items():
            assert value == pytest.approx(expected["com_sigma_parts"][key], rel=0, abs=1e-12)
        # They add in squares to the mean COM variance.
        assert sum(v * v for v in parts.values()) == pytest.approx(np.trace(run.com_offset_cov) / 2, rel=1e-9)
        # The arrays of the run: θ per frame, losses per sample, and their mean is the NMSE.
        n = len(recording)
        assert run.theta.shape == (n, 3) and run.std.shape == (n, 3)
        assert run.losses.shape == (n - 1, 2) and run.fixed_losses.shape == (n - 1, 2)
        np.testing.assert_allclose(run.losses.mean(axis=0), [run.nmse["pos"], run.nmse["rot"]], rtol=1e-12)
        np.testing.assert_array_equal(run.theta[0], run.theta0)
        np.testing.assert_array_equal(run.theta[-1], run.theta_end)


def test_after_goes_on_from_the_push_before_as_eval_carry_theta(model_file, cli, tmp_path):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--optimizer", "gauss-newton", "--carry-theta",
        "--offline", *map(str, OFFLINE[:3]), "--online", *map(str, ONLINE[:3]), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())["trajectories"]
    model = pushlab.Model.load(model_file)
    run = None
    for recording, expected in zip(pushlab.load(ONLINE[:3]), report):
        previous, run = run, model.online(recording, optimizer="gauss-newton", after=run)
        assert run.continued == expected["continued"] == (previous is not None)
        if previous is not None:
            np.testing.assert_array_equal(run.theta[0], previous.theta_end)
        for key in ("pos", "rot"):
            assert run.nmse[key] == pytest.approx(expected["online"][key], rel=0, abs=1e-12)
        np.testing.assert_allclose(run.theta_end, [*expected["com_offset_learned"], expected["h_learned"]], rtol=0, atol=1e-12)
        np.testing.assert_allclose(run.com_offset_cov, expected["com_offset_cov"], rtol=0, atol=1e-12)

    # A push of another object (another folder) is refused, naming both.
    other = pushlab.load(SET.parent / "box2-paper-center-front" / "online_000.csv")[0]
    with pytest.raises(ValueError, match="pushes another object than .*box2-paper-center-front"):
        model.online(other, after=run)


def test_start_com_shift_is_eval_start_com_shift(model_file, cli, tmp_path):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--optimizer", "gauss-newton",
        "--start-com-shift", "0.03,-0.02",
        "--offline", *map(str, OFFLINE[:3]), "--online", *map(str, ONLINE[:2]), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())
    assert report["config"]["start_com_shift"] == [0.03, -0.02]
    model = pushlab.Model.load(model_file)
    for recording, expected in zip(pushlab.load(ONLINE[:2]), report["trajectories"]):
        run = model.online(recording, optimizer="gauss-newton", start_com_shift=(0.03, -0.02))
        assert not run.continued
        np.testing.assert_allclose(run.theta[0], [*expected["theta_start"]["com_offset"], expected["theta_start"]["h"]], rtol=0, atol=1e-12)
        np.testing.assert_allclose(run.theta[0][:2], run.theta0[:2] + [0.03, -0.02], rtol=0, atol=1e-12)
        for key in ("pos", "rot"):
            assert run.nmse[key] == pytest.approx(expected["online"][key], rel=0, abs=1e-12)
        np.testing.assert_allclose(run.theta_end, [*expected["com_offset_learned"], expected["h_learned"]], rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="a run going on from `after` starts where that run ended"):
        model.online(recording, after=run, start_com_shift=(0.01, 0.0))


@pytest.mark.parametrize("carry", [False, True])
def test_physics_online_is_eval_physics(model_file, cli, tmp_path, carry):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--optimizer", "gauss-newton", "--physics",
        "--contact-tolerance", "0.02", *(["--carry-theta"] if carry else []),
        "--offline", *map(str, OFFLINE[:3]), "--online", *map(str, ONLINE[:3]), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())
    expected_runs = report["physics_trajectories"]
    assert len(expected_runs) == 3
    model = pushlab.Model.load(model_file)
    run, losses = None, []
    for recording, expected in zip(pushlab.load(ONLINE[:3]), expected_runs):
        run = model.physics_online(
            recording, optimizer="gauss-newton", contact_tolerance=0.02, after=run if carry else None
        )
        assert run.physics_only and run.continued == (carry and len(losses) > 0)
        np.testing.assert_allclose(run.theta_end, [*expected["com_offset_learned"], expected["h_learned"]], rtol=0, atol=1e-12)
        np.testing.assert_allclose(run.com_offset_cov, expected["com_offset_cov"], rtol=0, atol=1e-12)
        assert run.com_found["error_m"] == pytest.approx(expected["com_found"]["error_m"], rel=0, abs=1e-12)
        for key in ("pos", "rot"):
            assert run.nmse[key] == pytest.approx(expected["online"][key], rel=0, abs=1e-12)
            assert run.fixed_nmse[key] == pytest.approx(expected["fixed"][key], rel=0, abs=1e-12)
        losses.append(run.losses)
    # The report's physics-only online NMSE is the mean over every push's samples.
    mean = np.concatenate(losses).mean(axis=0)
    assert mean == pytest.approx([report["physics"]["online"]["pos"], report["physics"]["online"]["rot"]], rel=1e-12)
    # It learned: θ moved, and not as the combined model's run did.
    combined = model.online(pushlab.load(ONLINE[0])[0], optimizer="gauss-newton")
    first = model.physics_online(pushlab.load(ONLINE[0])[0], optimizer="gauss-newton", contact_tolerance=0.02)
    assert not np.allclose(first.theta_end, first.theta0) and not np.allclose(first.theta_end, combined.theta_end)
    # A run goes on only from a run of its own model.
    with pytest.raises(ValueError, match="a run of the combined model .*physics-only model"):
        model.physics_online(pushlab.load(ONLINE[1])[0], after=combined)
    with pytest.raises(ValueError, match="a run of the physics-only model .*combined model"):
        model.online(pushlab.load(ONLINE[1])[0], after=first)
    with pytest.raises(ValueError, match="contact_tolerance: must be a finite number of metres above 0, got -0.01"):
        model.physics_online(pushlab.load(ONLINE[1])[0], contact_tolerance=-0.01)


def test_weighed_with_is_eval_physics_weighted(model_file, cli, tmp_path):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--physics", "--offline", *map(str, OFFLINE[:3]),
        "--online", *map(str, ONLINE[:3]), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())
    model = pushlab.Model.load(model_file)
    for recording, expected in zip(pushlab.load(ONLINE[:3]), report["physics_trajectories"]):
        combined, physics = model.online(recording), model.physics_online(recording)
        weighted = combined.weighed_with(physics)
        for key in ("pos", "rot"):
            assert weighted["nmse"][key] == pytest.approx(expected["weighted"][key], rel=0, abs=1e-12)
        assert weighted["weight_end"] == pytest.approx(
            [expected["weight_end"]["pos"], expected["weight_end"]["rot"]], rel=0, abs=1e-12
        )
        weights = weighted["weights"]
        assert weights.shape == (combined.steps, 3)
        assert ((weights[:, 1:] > 0) & (weights[:, 1:] < 1)).all()
    with pytest.raises(ValueError, match="weighed_with: call it on a combined model's run"):
        physics.weighed_with(combined)


def test_best_fit_is_eval_best_fit(model_file, cli, tmp_path):
    report_path = tmp_path / "eval.json"
    run_cli(
        cli, "eval", "--model", str(model_file), "--physics", "--best-fit",
        "--offline", *map(str, OFFLINE[:3]), "--online", *map(str, ONLINE[:2]), "--json", str(report_path),
    )
    report = json.loads(report_path.read_text())
    model = pushlab.Model.load(model_file)
    for recording, combined, physics in zip(
        pushlab.load(ONLINE[:2]), report["trajectories"], report["physics_trajectories"]
    ):
        for fit, push in [(model.best_fit(recording), combined), (model.best_fit(recording, physics=True), physics)]:
            expected = push["best_fit"]
            np.testing.assert_allclose(fit["theta"]["com_offset"], expected["theta"]["com_offset"], rtol=0, atol=1e-12)
            assert fit["theta"]["h"] == pytest.approx(expected["theta"]["h"], rel=0, abs=1e-12)
            assert fit["samples"] == expected["samples"] == combined["steps"]
            for key in ("pos", "rot"):
                assert fit["nmse"][key] == pytest.approx(expected["nmse"][key], rel=0, abs=1e-12)
            assert fit["com_error_m"] == pytest.approx(expected["com_error_m"], rel=0, abs=1e-12)
            # The best θ fits the push at least as well as θ_online(0), the fixed run's.
            assert fit["mean_loss"] <= 2 * push["fixed"]["pos"] + push["fixed"]["rot"] + 1e-12
    with pytest.raises(ValueError, match="contact_tolerance: must be a finite number of metres above 0"):
        model.best_fit(pushlab.load(ONLINE[0])[0], physics=True, contact_tolerance=0.0)


def test_bad_tracking_frames_hold_theta(model_file, set_copy):
    labels = pushlab.Labels(set_copy)
    labels.paint("online_001.csv", "bad tracking", 20, 30)
    labels.save()
    recording = pushlab.load(set_copy / "online_001.csv")[0]
    run = pushlab.Model.load(model_file).online(recording)
    held = np.isnan(run.losses[:, 0])
    # A sample from frame k to k + 1 is held when either frame is labelled: frames 19..29.
    np.testing.assert_array_equal(np.flatnonzero(held), np.arange(19, 30))
    np.testing.assert_array_equal(run.theta[20:31], np.repeat(run.theta[19:20], 11, axis=0))
    assert run.steps == len(recording) - 1 - 11


def test_predict_uses_theta0_or_the_theta_given(model_file):
    model = pushlab.Model.load(model_file)
    recording = pushlab.load(ONLINE[0])[0]
    p = model.predict(recording, 30)
    assert p.frame == 30
    np.testing.assert_array_equal(p.theta, model.theta0(recording))
    assert np.isfinite(p.translation).all() and np.isfinite(p.rotation)
    assert p.loss_pos >= 0 and p.loss_rot >= 0
    moved = model.predict(recording, 30, theta=[0.05, 0.0, p.theta[2]])
    assert moved.theta == [0.05, 0.0, p.theta[2]]
    assert moved.to_dict()["observed_translation"] == p.observed_translation
    with pytest.raises(IndexError, match="has no sample"):
        model.predict(recording, len(recording) - 1)
    # A θ the model does not accept is refused, not predicted with (h = 0 divides by zero).
    with pytest.raises(ValueError, match=r"theta: h must be a finite number of metres in \[0.001, 2\], got 0"):
        model.predict(recording, 30, theta=[0.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="theta: COM offset x must be a finite number"):
        model.predict(recording, 30, theta=[float("nan"), 0.0, 0.05])


def test_bad_options_raise(model_file):
    model = pushlab.Model.load(model_file)
    recording = pushlab.load(ONLINE[0])[0]
    with pytest.raises(ValueError, match="gauss-newton"):
        model.online(recording, optimizer="adam")
    with pytest.raises(ValueError, match="unknown model kind"):
        pushlab.Model.train([recording], kind="big")
    with pytest.raises(pushlab.PushlabError, match="nothing to train on: no recordings given"):
        pushlab.Model.train([])
    # No epoch would be the random initial network, not a model.
    with pytest.raises(pushlab.PushlabError, match="epochs must be at least 1"):
        pushlab.Model.train([recording], epochs=0)
    with pytest.raises(pushlab.PushlabError, match="learning rate must be positive, got -0.01"):
        pushlab.Model.train([recording], adam_lr=-0.01)


def test_adams_learning_rate_goes_into_the_training_report():
    model = pushlab.Model.train(pushlab.load(OFFLINE)[:2], epochs=1, adam_lr=0.001, com_calibration=False)
    assert model.training["report"]["config"]["learning_rate"] == 0.001


def test_a_bad_model_file_raises_naming_the_file_and_field(model_file, tmp_path):
    data = json.loads(model_file.read_text())
    data["combined"]["horizon"] = 0
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(pushlab.PushlabError) as raised:
        pushlab.Model.load(bad)
    assert str(bad) in str(raised.value) and "horizon" in str(raised.value)
    with pytest.raises(pushlab.PushlabError, match="not a pushlab model file"):
        (tmp_path / "other.json").write_text('{"format": "something else"}')
        pushlab.Model.load(tmp_path / "other.json")
