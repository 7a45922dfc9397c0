"""The guide's walk-through (docs/src/python.md) runs as written: its ```python cells, in order."""

import os
import re

import pytest

from conftest import MIT, REPO, SAMPLE

PAGE = REPO / "docs" / "src" / "python.md"


def cells():
    return re.findall(r"^```python\n(.*?)^```$", PAGE.read_text(), flags=re.S | re.M)


def test_the_page_has_the_walk_through():
    text = "\n".join(cells())
    for call in ["pushlab.load(", "Model.train(", ".online(", "fill_between", "pushlab.Labels(", "pushlab.simulate("]:
        assert call in text


@pytest.mark.skipif(not MIT.is_dir(), reason=f"{MIT} absent: the guide's walk-through loads the MIT files from it")
def test_the_walk_through_runs(tmp_path, monkeypatch):
    # The cells use paths from the repository's root: ../shared/mit-push and sample-data/. Run them in
    # a scratch folder laid out the same way, so that the figure they save lands there.
    root = tmp_path / "repo"
    root.mkdir()
    (tmp_path / "shared").symlink_to(MIT.parent)
    (root / "sample-data").symlink_to(SAMPLE)
    monkeypatch.chdir(root)
    os.environ["MPLBACKEND"] = "Agg"
    namespace = {}
    for i, cell in enumerate(cells()):
        try:
            exec(compile(cell, f"{PAGE}:cell{i + 1}", "exec"), namespace)
        except Exception as e:
            raise AssertionError(f"cell {i + 1} of {PAGE} failed:\n{cell}") from e
    assert (root / "theta.png").stat().st_size > 10_000
    run, test = namespace["run"], namespace["test"]
    assert run.theta.shape == (len(test), 3)
