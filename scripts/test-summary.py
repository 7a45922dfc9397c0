"""What `bash scripts/test` ran, in one line at its end: how many tests ran, how many were skipped
and why.

A Rust test that cannot run here (the real recordings beside the repository, ffmpeg, poppler)
returns early, and `cargo test` counts it as passed and hides what it printed; it writes its name
and reason to the skip file (tests/skip.rs), which is read here. pytest and node's test runner
count their own skips.

    python3 scripts/test-summary.py SKIPPED CARGO_LOG PYTEST_LOG NODE_LOG
"""

import collections
import re
import sys


def read(path):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.read()
    except FileNotFoundError:
        return ""


def cargo_counts(log):
    """Passed, failed and ignored over every `test result:` line."""
    counts = collections.Counter()
    for m in re.finditer(r"test result: \w+\. (\d+) passed; (\d+) failed; (\d+) ignored", log):
        counts["passed"] += int(m[1])
        counts["failed"] += int(m[2])
        counts["ignored"] += int(m[3])
    return counts


def pytest_counts(log):
    """pytest's last summary line ("45 passed, 2 skipped in 30.1s"), and its skip reasons (-rs)."""
    counts = collections.Counter()
    summary = [line for line in log.splitlines() if re.search(r"\d+ (passed|failed|skipped)", line)]
    if summary:
        for number, what in re.findall(r"(\d+) (passed|failed|skipped|errors?)", summary[-1]):
            counts[what.rstrip("s") if what.startswith("error") else what] += int(number)
    reasons = re.findall(r"^SKIPPED \[(\d+)\] [^:]+:\d+: (.*)$", log, re.MULTILINE)
    return counts, [(int(n), why) for n, why in reasons]


def node_counts(log):
    """node --test's totals, from its TAP (`# pass 10`) or spec (`ℹ pass 10`) reporter."""
    counts = collections.Counter()
    for what, number in re.findall(r"^[#ℹ] (tests|pass|fail|skipped|todo) (\d+)$", log, re.MULTILINE):
        counts[what] = int(number)
    return counts


def main():
    skipped_file, cargo_log, pytest_log, node_log = sys.argv[1:5]
    skips = [line.split("\t", 1) for line in read(skipped_file).splitlines() if "\t" in line]
    cargo = cargo_counts(read(cargo_log))
    pytest, pytest_reasons = pytest_counts(read(pytest_log))
    node = node_counts(read(node_log))

    why = collections.Counter()
    for test, reason in skips:
        why[f"need {reason}"] += 1
        print(f"scripts/test: skipped {test}: needs {reason}")
    for number, reason in pytest_reasons:
        why[f"Python: {reason}"] += number
        print(f"scripts/test: skipped {number} Python test(s): {reason}")
    node_skipped = node["skipped"] + node["todo"]
    if node_skipped:
        why["page tests marked skip or todo"] += node_skipped

    rust_ran = cargo["passed"] + cargo["failed"] - len(skips)
    python_ran = pytest["passed"] + pytest["failed"] + pytest["error"]
    page_ran = node["pass"] + node["fail"]
    skipped = len(skips) + pytest["skipped"] + node_skipped
    reasons = "; ".join(f"{n} {r}" for r, n in why.most_common())
    line = (
        f"scripts/test: {rust_ran + python_ran + page_ran} tests ran "
        f"({rust_ran} Rust, {python_ran} Python, {page_ran} page), "
        f"{cargo['failed'] + pytest['failed'] + pytest['error'] + node['fail']} failed; "
        f"{skipped} skipped"
    )
    if skipped:
        line += f" ({reasons})"
    if cargo["ignored"]:
        line += f"; {cargo['ignored']} Rust tests ignored"
    print(line)


if __name__ == "__main__":
    main()
