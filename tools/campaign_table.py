"""The contract campaign's table for docs/robustness.md, from the JSON lines of ``make fuzz``.

    python tools/campaign_table.py campaign.jsonl
"""

from __future__ import annotations

import json
import sys


def row(r: dict) -> str:
    silent = f"**{r['silent']}**" if r["silent"] else "0"
    within = "–" if r["no_claim"] else str(r["within"])
    return (f"| {r['analysis']} | {r['method']} | {r['answers']} | {within} | {r['warned']} ({r['covered']}) | "
            f"{r['refused']} | {r['crashed']} | {r['over_time']} | {r['no_claim']} | {silent} | {r['largest']:.1e} |")


def main(path: str) -> None:
    rows = [json.loads(line) for line in open(path) if line.strip()]
    order = ["modes", "frequency_response", "simulate", "reduce", "static"]
    rows.sort(key=lambda r: (order.index(r["analysis"]) if r["analysis"] in order else 99,
                             r["method"] == "auto", r["method"]))
    print("| analysis | method | answers | within | warned (covering) | refused | crashed | over 5 s | no claim | "
          "silent | largest error |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(row(r))


if __name__ == "__main__":
    main(sys.argv[1])
