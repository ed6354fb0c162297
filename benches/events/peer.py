"""The peer of benches/events.rs: the adversarial cases of declared events through scipy's
solve_ivp with event functions (scripts/bench-events installs scipy into target/bench-venv).

Reads the cases the bench exported (argv[1]) and writes, as JSON on stdout, every event time
solve_ivp reports for each case's events, for RK45 at the default tolerances (rtol 1e-3, atol
1e-6) and at rtol 1e-10, atol 1e-12. Each event function is the case's own: a plane's n . p - d,
the apex's V.z, a speed's |V| - s; direction +1 (rising), -1 (falling) or 0; terminal=False (a
stop count is applied afterwards: the first n occurrences). The state is (p, V) under gravity,
or on a zero-rest-length spring (a = -k (p - anchor)), mass 1.
"""

import json
import sys
import time

import numpy as np
import scipy
from scipy.integrate import solve_ivp


def rhs_of(case):
    g = np.array(case["g"], dtype=float)
    spring = case.get("spring")
    if spring is None:
        def rhs(t, y):
            return np.concatenate((y[3:], g))
    else:
        anchor = np.array(spring["anchor"], dtype=float)
        k = float(spring["stiffness"])

        def rhs(t, y):
            return np.concatenate((y[3:], g - k * (y[:3] - anchor)))
    return rhs


def event_of(w):
    kind = w["kind"]
    if kind == "plane":
        n = np.array(w["n"], dtype=float)
        d = float(w["d"])

        def f(t, y):
            return float(n @ y[:3] - d)
    elif kind == "apex":
        def f(t, y):
            return float(y[5])
    else:
        s = float(w["speed"])

        def f(t, y):
            return float(np.linalg.norm(y[3:]) - s)
    f.terminal = False
    f.direction = {"rising": 1.0, "falling": -1.0}.get(w["direction"], 0.0)
    return f


SETTINGS = [
    ("RK45, default tolerances (rtol 1e-3, atol 1e-6)", {}),
    ("RK45, rtol 1e-10, atol 1e-12", {"rtol": 1e-10, "atol": 1e-12}),
]


def main():
    cases = json.load(open(sys.argv[1]))["cases"]
    out = {"scipy": scipy.__version__, "numpy": np.__version__, "settings": []}
    for label, opts in SETTINGS:
        results = []
        errors = 0
        t0 = time.process_time()
        for case in cases:
            y0 = np.array(case["p0"] + case["v0"], dtype=float)
            events = [event_of(w) for w in case["watches"]]
            try:
                sol = solve_ivp(rhs_of(case), (0.0, case["horizon"]), y0, method="RK45",
                                events=events, **opts)
                times = []
                for w, te in zip(case["watches"], sol.t_events):
                    te = [float(x) for x in te]
                    if w.get("stop"):
                        te = te[: w["stop"]]
                    times.append(te)
                results.append({"index": case["index"], "times": times, "error": None})
            except Exception as e:  # a crash counts as every occurrence missed
                errors += 1
                results.append({"index": case["index"], "times": [[] for _ in case["watches"]],
                                "error": f"{type(e).__name__}: {e}"})
        out["settings"].append({"label": label, "results": results, "crashes": errors,
                                "cpu_seconds": time.process_time() - t0})
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
