"""What ``pfem-skfem run`` says of a run (issue 56, items 3 and 4): what it is before the
first step (particles, steps, dt) and what it will cost after it (elements, seconds);
a step too long for the method, once, with the step where it first happened and dt; and
at the end why it stopped (t_end or the steps asked reached, at rest since step N or
still consolidating, no material left, a solver failure) with its main figures.

Plain functions of the scene and the step records (``history.json``'s dicts), so that
they read a resumed run's records as they read a new one's.
"""
import math

#: A step may move a particle at most this many spacings h (the record's
#: ``max_displacement_over_h``, a Courant number of the step). A step is one linearisation
#: on one mesh, and the next mesh is the alpha-shape (alpha ~ 1.3-1.6 h) of the particles
#: where the step left them: a particle that passes its neighbours' elements (more than
#: two spacings) has left the body the mesh described, and its elements would have
#: inverted. One spacing is usual at a fast front: the dam break example at its own dt
#: moves its front 0.98 h a step, the column example 0.07 h; dt = 0.5 in the column
#: example (156 times its own) moves particles 7.8-13 h a step.
MAX_DISPLACEMENT_OVER_H = 2.0

#: The meshed area (a volume in axisymmetry) may change by at most this fraction from
#: one step to the next (the records' ``area_change``; in a scene without outlets). The
#: material is (nearly) incompressible, or dilates by a few per cent over
#: a whole collapse: 5 % in one step is the alpha-shape losing (or making up) material,
#: not the material's own change. The column example at its own dt stays below 0.6 %, the dam
#: break example's splash below 1.5 %; dt = 0.5 in the column example loses 15-21 % a step.
MAX_AREA_STEP_CHANGE = 0.05

#: A run is at rest when its largest speed is below this fraction of sqrt(|g| L) (L the
#: scene's length): the column example's reaches 7e-11 m/s, a falling one 1 m/s.
REST_SPEED = 1e-6

#: The exit code of a run that finished but whose steps broke a bound above (0: done,
#: 2: it could not start, 3: a solver failure or a full disk, 130/143: interrupted).
EXIT_TOO_LONG_STEPS = 4


def rest_speed(scene):
    """The speed below which ``scene`` is at rest: REST_SPEED sqrt(|g| L)."""
    g = math.hypot(*scene.gravity)
    return REST_SPEED * math.sqrt((g or 1.0) * scene.length)


def _mass_before(records, i):
    """The mass inside at the start of step ``records[i]`` (the mass of its mesh)."""
    if i > 0:
        return records[i - 1]["mass"]
    first = records[0]
    return first["mass"] + sum(first.get("discharged", {}).values())


def step_too_long(records, i):
    """Why the step of ``records[i]`` broke a bound, or None: (what, figure, unit, bound).

    The area of a record is that of its step's mesh, made of the particles at the step's
    start: its change from the record before is the previous step's. It is not compared
    in a scene with outlets (its records name them), whose mesh loses the particles that
    leave steps before the outlet takes them (the silo's hopper loses 5 % in a step at
    the thesis' dt), nor in a step of no mesh (every particle free).
    """
    record = records[i]
    moved = record.get("max_displacement_over_h", 0.0)
    if moved > MAX_DISPLACEMENT_OVER_H:
        return ("moved particles", moved, "spacings h", MAX_DISPLACEMENT_OVER_H)
    if (i == 0 or record.get("discharged") or not record.get("elements")
            or not records[i - 1].get("elements")):
        return None
    change = (1 + record["area_change"]) / (1 + records[i - 1]["area_change"]) - 1
    if abs(change) > MAX_AREA_STEP_CHANGE:
        return ("changed the area by", change, "", MAX_AREA_STEP_CHANGE)
    return None


def too_long_message(records, i, dt):
    """The warning on ``records[i]``'s step (:func:`step_too_long` not None)."""
    what, figure, unit, bound = step_too_long(records, i)
    step = records[i]["step"]
    if unit:
        said = (f"step {step} {what} {figure:.3g} {unit} (more than {bound:g}: the "
                "next mesh cannot follow a particle past its neighbours)")
        shorter = dt * bound / figure
    else:
        said = (f"step {step - 1} {what} {figure:+.1%} (more than {bound:.0%}: material "
                "lost or made by the remeshing)")
        shorter = dt / 4
    return (f"warning: {said}: dt = {dt:.6g} s is too long for this scene (try dt <= "
            f"{shorter:.2g} s); the results are not to be trusted (exit code "
            f"{EXIT_TOO_LONG_STEPS} unless --force)")


def first_too_long(records):
    """The index of the first record whose step broke a bound, or None."""
    return next((i for i in range(len(records)) if step_too_long(records, i)), None)


def start_line(scene, state, first, last, out):
    """What the run is, before its first step."""
    until = (f"t = {state.time:.6g}-{state.time + (last - first) * scene.config.dt:.6g} s")
    return (f"steps {first + 1}-{last} of dt = {scene.config.dt:.6g} s ({until}), "
            f"{state.n} particles, into {out}/")


def estimate_line(record, seconds, steps):
    """After the first step: its elements and time, and the run's cost from it."""
    return (f"step {record['step']}: {record['elements']} elements, {seconds:.2g} s: "
            f"about {_duration(seconds * steps)} for the {steps} steps")


def _duration(seconds):
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


def at_rest_since(records, speed, pore_rate=0.0):
    """The step from which every record's ``max_speed`` is below ``speed`` to the end,
    and, in a saturated run, its ``pore_pressure_rate_max`` at most ``pore_rate``; or None
    (the last step moves or still drains)."""
    since = None
    for record in reversed(records):
        if (record["max_speed"] >= speed
                or record.get("pore_pressure_rate_max", 0.0) > pore_rate):
            break
        since = record["step"]
    return since


def rest_pore_rate(scene, records):
    """The rate of pore pressure below which a saturated run is at rest: REST_SPEED times
    the run's largest pore pressure (the records' ``pore_pressure_max``) in the time
    sqrt(L / |g|) that the speed bound takes as its unit; 0 in a dry run. A consolidating
    soil settles slower than the speed bound while it drains: the column of
    verification/consolidation_pfem.py (4 spacings) at 4e-7 m/s against 3e-6 from its
    second step, its pore pressure changing by 0.1-0.35 Pa/s (the records'
    ``pore_pressure_rate_max``) against this bound's 3e-4."""
    p = max((r.get("pore_pressure_max", 0.0) for r in records), default=0.0)
    g = math.hypot(*scene.gravity)
    return REST_SPEED * p * math.sqrt((g or 1.0) / scene.length)


def why_stopped(scene, state, records, last):
    """Why a run that raised nothing ended: no material left, t_end or the steps asked
    reached; at rest since step N when it is."""
    if state.n == 0:
        out = records[-1].get("discharged", {}) if records else {}
        where = ", ".join(out) or "the outlets"
        why = (f"no material left: every particle discharged (through {where}) by step "
               f"{state.step}, t = {state.time:.6g} s, before step {last}")
    elif scene.t_end is not None and state.time >= scene.t_end * (1 - 1e-9):
        why = f"t_end = {scene.t_end:.6g} s reached (step {state.step})"
    else:
        why = f"step {state.step} reached, as asked (t = {state.time:.6g} s)"
    rate = rest_pore_rate(scene, records)
    since = at_rest_since(records, rest_speed(scene), rate) if records and state.n else None
    if since is not None:
        why += (f"; at rest since step {since} (largest speed {records[-1]['max_speed']:.2g} "
                f"m/s < {rest_speed(scene):.2g})")
    elif records and state.n and "pore_pressure_rate_max" in records[-1]:
        why += (f"; still consolidating (the pore pressure changing by up to "
                f"{records[-1]['pore_pressure_rate_max']:.2g} Pa/s > {rate:.2g})")
    return why


def figures(state, records):
    """The run's main figures: steps, time, particles, mass kept, largest speed."""
    if not records:
        return f"step {state.step}, t = {state.time:.6g} s, {state.n} particles"
    last = records[-1]
    top = max(records, key=lambda r: r["max_speed"])
    now = (f"{last['max_speed']:.3g} m/s at the end, " if last["particles"] else "")
    n = last["step"]
    return (f"{n} step{'s' * (n != 1)}, t = {last['time']:.6g} s, {last['particles']} particles, "
            f"mass kept {100 * last['mass'] / _mass_before(records, 0):.6g} %, largest speed "
            f"{now}{top['max_speed']:.3g} m/s in the run (step {top['step']})")
