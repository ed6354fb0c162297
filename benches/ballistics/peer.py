"""The peer side of Volley's ballistics bench: py-ballisticcalc flies the bench's shot, and the
bundled rifle's shot for its range table.

The shot (the same one benches/ballistics.rs gives Volley): a G7 bullet of ballistic
coefficient 0.223 lb/in^2 leaving a level barrel at 2750 ft/s (838.2 m/s) with no sight height,
in the ICAO standard atmosphere at sea level with dry air, no wind, to 1000 m. Printed as JSON:
for each engine step (the default, RK4 at 2.5 ms, and finer ones, for the peer's own
convergence) the rows every 100 m (range m, height m, speed m/s, time s) and the median wall
time of one trajectory over the repeats.

The rifle (assets/scenes/rifle.ron): the same bullet (0.0109 kg) at 0.8397 degrees with a
3 m/s full-value crosswind from the right, to 1000 m; its rows every 100 m (range, height above
the muzzle, windage, speed, Mach, energy, time) at the compiled RK4's finest step, in the peer's
ICAO air (CIPM-2007 density, 1.22552 kg/m^3 at 15 C and 1013.25 hPa, dry) and in the same air
with the pressure scaled so the density is Volley's ICAO 1.225 kg/m^3.

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
    Angular,
    Distance,
    DragModel,
    Energy,
    Pressure,
    Shot,
    TableG7,
    Velocity,
    Weapon,
    Weight,
    Wind,
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


def rifle(atmo):
    """The bundled rifle's shot in `atmo`: rows every 100 m to 1000 m."""
    calc = Calculator(config={"cStepMultiplier": 0.01}, engine="cythonized_rk4_engine")
    shot = Shot(
        weapon=Weapon(sight_height=Distance.Meter(0)),
        ammo=Ammo(
            DragModel(0.223, TableG7, weight=Weight.Kilogram(0.0109)), Velocity.MPS(838.2)
        ),
        atmo=atmo,
        relative_angle=Angular.Degree(0.8397),
        # From the right (90 degrees): it blows the bullet to the left, Volley's +y.
        winds=[Wind(Velocity.MPS(3), Angular.Degree(90))],
    )
    rows = calc.fire(shot, Distance.Meter(1000), Distance.Meter(100)).trajectory
    return [
        [
            row.distance >> Distance.Meter,
            row.height >> Distance.Meter,
            row.windage >> Distance.Meter,
            row.velocity >> Velocity.MPS,
            row.mach,
            row.energy >> Energy.Joule,
            row.time,
        ]
        for row in rows
    ]


def rifle_tables():
    icao = Atmo.icao(humidity=0)
    hpa = icao.pressure >> Pressure.hPa
    matched = Atmo(
        altitude=Distance.Meter(0),
        pressure=Pressure.hPa(hpa / icao.density_ratio),
        temperature=icao.temperature,
        humidity=0,
    )
    return {
        "icao": {"density": icao.density_metric, "rows": rifle(icao)},
        "matched": {"density": matched.density_metric, "rows": rifle(matched)},
    }


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
    out["rifle"] = rifle_tables()
    json.dump(out, sys.stdout, indent=1)


if __name__ == "__main__":
    main()
