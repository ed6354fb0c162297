"""The peer side of Volley's ballistics bench: py-ballisticcalc flies the bench's shot.

The shot (the same one benches/ballistics.rs gives Volley): a G7 bullet of ballistic
coefficient 0.223 lb/in^2 leaving a level barrel at 2750 ft/s (838.2 m/s) with no sight height,
in the ICAO standard atmosphere at sea level with dry air, no wind, to 1000 m. Printed as JSON:
for each engine step (the default, RK4 at 2.5 ms, and finer ones, for the peer's own
convergence) the rows every 100 m (range m, height m, speed m/s, time s) and the median wall
time of one trajectory over the repeats.

Run by scripts/bench-ballistics inside its own virtual environment; never by the tests.
"""

import json
import statistics
import sys
import time
import warnings

import py_ballisticcalc
from py_ballisticcalc import (
    Ammo,
    Atmo,
    Calculator,
    Distance,
    DragModel,
    Shot,
    TableG7,
    Velocity,
    Weapon,
)

REPEATS = int(sys.argv[1]) if len(sys.argv) > 1 else 20

# The entry-point names and the `trajectory` alias are deprecated in 3.1 and still work.
warnings.simplefilter("ignore", DeprecationWarning)

# Its default engine (RK4 in Python) and the same RK4 compiled (py-ballisticcalc.exts).
ENGINES = ["rk4_engine", "cythonized_rk4_engine"]


def fly(engine, multiplier):
    config = {"cStepMultiplier": multiplier}
    calc = Calculator(config=config, engine=engine)
    shot = Shot(
        weapon=Weapon(sight_height=Distance.Meter(0)),
        ammo=Ammo(DragModel(0.223, TableG7), Velocity.FPS(2750)),
        atmo=Atmo.icao(humidity=0),
    )
    rows = calc.fire(shot, Distance.Meter(1000), Distance.Meter(100)).trajectory
    return [
        [
            row.distance >> Distance.Meter,
            row.height >> Distance.Meter,
            row.velocity >> Velocity.MPS,
            row.time,
        ]
        for row in rows
    ]


def main():
    out = {"peer": "py-ballisticcalc " + py_ballisticcalc.__version__, "runs": []}
    steps = [(1.0, REPEATS), (0.1, max(3, REPEATS // 5)), (0.01, 3)]
    for engine in ENGINES:
        for multiplier, repeats in steps:
            rows = fly(engine, multiplier)
            times = []
            for _ in range(repeats):
                start = time.perf_counter()
                fly(engine, multiplier)
                times.append(time.perf_counter() - start)
            out["runs"].append(
                {
                    "engine": engine,
                    "step_s": 0.0025 * multiplier,
                    "rows": rows,
                    "seconds_per_trajectory": statistics.median(times),
                    "repeats": repeats,
                }
            )
    json.dump(out, sys.stdout, indent=1)


if __name__ == "__main__":
    main()
