"""Issue 28's measure of the house: the calls of one FRF go back up a layer at most 8 times.

tools/layer_climbs.py follows the path one ``frequency_response`` of the built-in example really
takes (the profiler's calls, mapped through the layering test's LAYERS table) and counts the steps
into a higher layer; on the layout before issue 28 the same count was 12 (its static walk over every
method's branch, 21; now 18: reported, not held)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _tool():
    spec = importlib.util.spec_from_file_location("layer_climbs", ROOT / "tools" / "layer_climbs.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules["layer_climbs"] = mod            # dataclasses look their module up there
    spec.loader.exec_module(mod)
    return mod


def test_one_frf_climbs_at_most_8_times() -> None:
    lc = _tool()
    count, path = lc.trace(lc.example_frf())
    assert len(path) > 10, "the trace saw the FRF's modules"           # the profiler really followed it
    assert count <= 8, "\n".join(f"{lay} {mod}" for mod, lay in path)


def test_the_static_walk_reads_the_layer_table() -> None:
    lc = _tool()
    table = lc.layers()
    assert lc.layer_of("vibss.linear.plant.assemble", table) < lc.layer_of("vibss.frequency.api", table)
    count, path = lc.climbs()
    assert path[0][0] == "vibss.frequency.api"
    top = lc.layer_of("vibss.frequency.api", table)
    assert count > 0 and min(lay for _, lay in path) < top, "the walk went down into the core and back up"
