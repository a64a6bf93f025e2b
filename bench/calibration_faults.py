#!/usr/bin/env python3
"""The fault-injection matrix of MSG-Cal: simulated sessions of the must-show rig (an RGB-D reference, a
VLP-16, a 2D laser, two cameras; furnished room, a person holding the board, 3 Hz) each carrying one fault
of real sessions, calibrate_rig with its defaults (and --edges, as the must-show sessions), and per
sensor: right and trusted, wrong and flagged, right but flagged, wrong and NOT flagged (wrong: beyond
2 cm / 0.02 rad of the truth; flagged: withheld from the URDF and launch file). Sensors the fault does not
touch must stay within 1 cm / 0.01 rad (isolation).

usage: /usr/bin/python3 bench/calibration_faults.py [--work DIR] [--only NAME[,NAME...]] [--seed S]

Sessions are generated into --work (default /tmp/vocal_calibration_faults) once and reused.
"""
import argparse
import os
import re
import sys

import numpy as np
import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from calibration_sessions import MUST_SHOW, TOOLS, angle, calibrate, rotation, run  # noqa: E402

WRONG_T, WRONG_R = 0.02, 0.02        # the "wrong"
ISOLATED_T, ISOLATED_R = 0.01, 0.01  # what a sensor the fault does not touch must keep

# name, simulate_calibration_session flags, how to spoil the rig YAML (None: as written), sensors touched
FAULTS = [
    ("no fault", "", None, []),
    ("camera0 on a pan-tilt head (+-0.3 rad)", "--faults moves:camera0:0.3", None, ["camera0"]),
    ("lidar0 on a pan-tilt head (+-0.2 rad)", "--faults moves:lidar0:0.2", None, ["lidar0"]),
    ("camera1 bumped half way (3 cm, 30 mrad)", "--faults bumped:camera1:0.03", None, ["camera1"]),
    ("lidar0 bumped half way (3 cm, 30 mrad)", "--faults bumped:lidar0:0.03", None, ["lidar0"]),
    ("laser0 stamps 0.2 s late", "--faults time-offset:laser0:0.2", None, ["laser0"]),
    ("lidar0 clock 0.5 s late", "--faults time-offset:lidar0:0.5", None, ["lidar0"]),
    ("lidar0 clock 1.5 s late", "--faults time-offset:lidar0:1.5", None, ["lidar0"]),
    ("camera1 camera_info focal length +5 %", "--faults focal:camera1:1.05", None, ["camera1"]),
    ("rig YAML: board and squares 5 % too large", "", 1.05, ["lidar0", "laser0", "camera0", "camera1"]),
    ("lidar0: dark squares return nothing", "--dark-absorbs", None, ["lidar0"]),
    ("lidar0: +5 cm range offset on every ring", "--range-offset 0.05", None, ["lidar0"]),
    ("lidar0: +8 cm range offset on every ring", "--range-offset 0.08", None, ["lidar0"]),
    ("lidar0: per-ring range biases +-5 cm", "--ring-bias 0.05", None, ["lidar0"]),
    ("the board on a stand (two posts, feet), no one holding it", "--stand", None, []),
    ("lidar0 scan cropped to 1 m around the board", "--crop-lidar 1.0", None, ["lidar0"]),
    ("stand, dark squares return nothing, lidar0 cropped", "--stand --dark-absorbs --crop-lidar 1.0", None, ["lidar0"]),
]


def spoiled_rig(folder, scale):
    """The rig YAML with the target's size and squares scaled (what a user measuring the board wrongly writes)."""
    text = open(f"{folder}/rig.yaml").read()
    for key in ("square_size", "width", "height"):
        text = re.sub(rf"({key}: )([0-9.]+)", lambda m: m.group(1) + f"{float(m.group(2)) * scale:.4f}", text, count=1)
    path = f"{folder}/rig_spoiled.yaml"
    open(path, "w").write(text)
    return path


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--work", default="/tmp/vocal_calibration_faults")
    parser.add_argument("--only", default="")
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    only = [o for o in args.only.split(",") if o]
    rows, totals = [], {"right and trusted": 0, "wrong and flagged": 0, "right but flagged": 0, "wrong and NOT flagged": 0}
    isolation_failures = 0
    for name, flags, rig_scale, touched in FAULTS:
        if only and not any(o in name for o in only):
            continue
        folder = os.path.join(args.work, f"seed{args.seed}_" + re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_"))
        if not os.path.exists(f"{folder}/session.bag"):
            session = MUST_SHOW.replace(" --person", "") if "--stand" in flags else MUST_SHOW  # a stand holds it instead
            code, output, _ = run(f"{TOOLS}/simulate_calibration_session {folder} {session} --rate 3 --seed {args.seed} {flags}")
            if code != 0:
                print(f"{name}: simulation failed: {output}", file=sys.stderr)
                continue
        rig = spoiled_rig(folder, rig_scale) if rig_scale else f"{folder}/rig.yaml"
        truth = yaml.safe_load(open(f"{folder}/ground_truth.yaml"))
        result, output, seconds, code = calibrate(rig, f"{folder}/session.bag", "--edges", f"{folder}/out")
        if result is None:
            last = output.strip().splitlines()[-1][:120] if output.strip() else "no output"
            rows.append((name, f"no result: {last}", "", "", f"{seconds:.0f} s, exit {code}"))
            print(f"done: {name} (no result)", file=sys.stderr)
            continue
        cells, untouched = [], []
        for s, t in zip(result["sensors"][1:], truth["sensors"][1:]):
            p = t["pose"]
            dt = np.linalg.norm(np.array(s["translation"]) - p[:3])
            dr = angle(rotation(p[3:]), rotation(s["rotation"]))
            wrong = dt > WRONG_T or dr > WRONG_R
            flagged = s.get("published") is False
            verdict = ("wrong and flagged" if flagged else "wrong and NOT flagged") if wrong else (
                "right but flagged" if flagged else "right and trusted")
            totals[verdict] += 1
            cells.append(f"{s['name']} {1000 * dt:.1f} / {1000 * dr:.1f} {verdict.replace('and ', '').replace('but ', '')}")
            if s["name"] not in touched:
                ok = dt <= ISOLATED_T and dr <= ISOLATED_R
                untouched.append(f"{s['name']} {'ok' if ok else 'MOVED'}")
                isolation_failures += not ok
        isolated = ", ".join(s["name"] for s in result["sensors"] if s.get("isolated")) or "none"
        rows.append((name, "; ".join(cells), isolated, ", ".join(untouched) or "-", f"{seconds:.0f} s, exit {code}"))
        print(f"done: {name}", file=sys.stderr)
    print("| fault | per sensor: error mm / mrad, verdict | isolated | untouched sensors within 1 cm / 0.01 rad | run |")
    print("|---|---|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")
    print()
    print("totals: " + ", ".join(f"{k} {v}" for k, v in totals.items()) + f"; untouched sensors moved: {isolation_failures}")


if __name__ == "__main__":
    main()
