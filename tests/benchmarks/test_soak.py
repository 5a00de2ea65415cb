"""The soak benchmark in private mode, for a few seconds: sessions come and go, every one is freed."""

from __future__ import annotations

import re

from benchmarks.soak import main


def test_a_short_private_soak_frees_every_session_and_writes_after_each_sample(tmp_path):
    out = tmp_path / "soak.md"
    main(["--minutes", "0.1", "--mode", "private", "--every", "2", "--out", str(out)])
    text = out.read_text()
    # The header says how long it ran: at least what was asked, more on a loaded machine (the last round of
    # joins and its sample end after the time is up).
    header = re.match(r"# Soak: (\d+\.\d) of 0\.1 minutes of joins and leaves \(private mode\)\n", text)
    assert header is not None, text[:200]
    assert "`python -m benchmarks.soak --minutes 0.1 --mode private --every 2`" in text
    rows = [line.split("|")[1:-1] for line in text.splitlines() if line.startswith("| ") and line[2].isdigit()]
    # The first sample comes after the first joins and leaves, then one every 2 s and one at the end (as many
    # as a loaded machine gets through): joins only grow, and the last row is after the run's end.
    joins = [int(row[1]) for row in rows]
    assert rows and joins == sorted(joins) and joins[-1] >= 1 and float(rows[-1][0]) >= 0.1
    for row in rows:
        assert float(row[2]) > 0.0  # resident memory
        assert row[3].strip() == row[4].strip() == "0"  # no session, no client left once everyone left
    assert float(header.group(1)) >= max(0.1, float(rows[-1][0]))  # written after the last sample
    assert rows[-1][5].strip() == "0"  # and no Simulation alive after a collection
