#!/usr/bin/env python3
"""Prints a mechgen model of a single-crankshaft reciprocating engine (Paul §6.8, DYREC).

    tools/make_engine.py --preset inline4 [options] > models/engine_inline4.yaml

One planar model: a crank link (the crankshaft with its flywheel) pivoted at O = (0, 0) on
the frame, carrying one crank pin B_j per cylinder at radius r and throw angle gamma_j in the
crank's frame; for each cylinder j a connecting rod rod_j (B_j to the wrist pin C_j, length
l) and a piston piston_j sliding on the cylinder axis: the line at the bank angle beta_j
through the point e n_j of the frame (e: the cylinder offset, desaxe; n_j = (-sin beta_j,
cos beta_j)). The slide s_slide_j is measured outward (from the crank towards the cylinder
head) from that point. Cylinders at different axial positions z_j of a real crankshaft are
superposed in the plane; the planar motion does not use z_j, but the rocking couples (about
axes across the crankshaft) of mechgen/machines/engine/couples.h do: rod_j and piston_j act at z_j.

Conventions: the crank angle theta_crank is CCW +; an in-line engine's cylinders point along
+x, so cylinder j is at top dead centre (TDC) where theta_crank + gamma_j = beta_j +
asin(e/(l + r)). V engines have their banks at +-V/2 about +x, a boxer at 0 and 180 deg, a
radial's cylinders every 360/n deg, all its rods on one crank pin (each rod its own pin
point at the same place: a fork-and-blade, not a master and articulated rods).

Firing: phase_j is the crank angle of cylinder j's firing TDC. The first cylinder of the
firing order fires at its TDC in [0, 360) deg; each next one at its TDC (one of two over a
four-stroke cycle of 720 deg) nearest to the previous firing plus cycle/n and after it
(two-stroke: its one TDC in the cycle after the first). The phases are numbers computed at
the maker's geometry (with an offset they move when r, l or e change at run time).

Gas: each piston carries the load p_gas_j A (A = pi bore^2/4) along its axis, away from the
cylinder head, with p_gas_j a parameter (gauge pressure, Pa; default 0): a tool sets it at run
time (Params::Find) for bearing loads and side thrust at a crank angle (kinetostatics). For
the motion, the engine tool adds the gas torque -sum p_j(theta - phase_j) A ds_j/dtheta from
its pressure law through mechgen/machines/engine/crank_dynamics.h (GasTorque), with p_gas_j = 0.

Load: the torque -(T_load + c_load theta_crank_dot) on the crank (N m). Gravity off.
Bad arguments: a message on stderr, exit status 2, nothing on stdout.
"""

import argparse
import math
import shlex
import sys

# name: (throws gamma_j deg, banks beta_j deg, firing order (1-based)). The names and the
# throws and banks are those of mechgen_balance's layouts (mechgen/machines/balancing/
# engine_balance.h, `mechgen_balance layouts`; tests/engine/layout_names_test.py checks that
# every preset here is a layout there, cylinder by cylinder).
PRESETS = {
    "single": ([0], [0], [1]),
    "inline2_180": ([0, 180], [0, 0], [1, 2]),
    "inline2_360": ([0, 0], [0, 0], [1, 2]),
    "inline3": ([0, 120, 240], [0, 0, 0], [1, 2, 3]),
    "inline4": ([0, 180, 180, 0], [0, 0, 0, 0], [1, 3, 4, 2]),
    "inline5": ([0, 216, 144, 72, 288], [0] * 5, [1, 2, 4, 5, 3]),
    "inline6": ([0, 240, 120, 120, 240, 0], [0] * 6, [1, 5, 3, 6, 2, 4]),
    # 60 deg V6, six split pins 60 deg apart, even firing every 120 deg; cylinders 1-3 on the
    # bank at +30 deg, 4-6 at -30 deg.
    "v6_60": ([30, 150, 270, 210, 330, 90], [30, 30, 30, -30, -30, -30], [1, 4, 2, 5, 3, 6]),
    # 90 deg cross-plane V8: pins at 0, 90, 270, 180 deg, cylinder i (bank +45 deg) and i + 4
    # (bank -45 deg) on pin i; even firing every 90 deg.
    "v8_crossplane": ([0, 90, 270, 180, 0, 90, 270, 180], [45] * 4 + [-45] * 4, [1, 8, 4, 5, 7, 3, 6, 2]),
    # 90 deg V-twin (L-twin), both rods on one pin: firing intervals 270/450 deg.
    "vtwin90": ([0, 0], [45, -45], [1, 2]),
    # flat four: opposed pistons move in opposite directions (each pair on pins 180 deg apart).
    "boxer4": ([0, 180, 180, 0], [0, 180, 0, 180], [1, 3, 2, 4]),
    "radial5": ([0] * 5, [0, 72, 144, 216, 288], [1, 3, 5, 2, 4]),
}

# The presets' earlier names (before they took mechgen_balance's): refused with the new name.
RENAMED = {"inline2": "inline2_180", "v6": "v6_60", "v8": "v8_crossplane", "vtwin": "vtwin90"}
V_PRESETS = ("v6_60", "v8_crossplane", "vtwin90")


class UsageError(Exception):
    pass


# The ranges every number of the command line must lie in (finite always): lengths up to
# 1 km, masses and inertias up to 1e6 (kg, kg m^2), load torques up to 1e7 N m (N m s/rad),
# angles within two turns either way. Beyond them the model's arithmetic (l^2 - (e - b)^2,
# the phases) stops being meaningful long before it overflows to inf or nan.
MAX_LENGTH = 1e3
MAX_MASS = 1e6
MAX_LOAD = 1e7
MAX_ANGLE = 720.0


def number(text, what, lo, hi, lo_open=False, hi_open=False, unit=""):
    """text as a finite float in [lo, hi] (an open end excludes it), else a UsageError."""
    try:
        x = float(text)
    except (TypeError, ValueError):
        raise UsageError(f"{what}: a number is needed, got '{text}'")
    above = x > lo if lo_open else x >= lo
    below = x < hi if hi_open else x <= hi
    if not (math.isfinite(x) and above and below):
        interval = f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
        raise UsageError(f"{what} must be a finite number in {interval}{unit}, got '{text}'")
    return x


def numeric(what, lo, hi, lo_open=False, hi_open=False, unit=""):
    """An argparse type: a finite number in range (see number)."""
    def parse(text):
        return number(text, what, lo, hi, lo_open, hi_open, unit)
    parse.__name__ = "number"
    return parse


def fmt(x):
    """A number as a plain YAML/model number (repr: round-trips, deterministic)."""
    if not math.isfinite(x):
        # Every input is checked finite and in range; a non-finite result is a bug here.
        raise UsageError(f"internal error: a non-finite number ({x!r}) would be written")
    if x == 0:
        return "0.0"
    s = repr(float(x))
    return s


def number_list(text, what, lo, hi, unit):
    vals = []
    for v in text.split(","):
        try:
            float(v)
        except ValueError:
            raise UsageError(f"--{what}: a comma-separated list of numbers ({unit.strip()}), got '{text}'")
        vals.append(number(v, f"--{what}: each value", lo, hi, unit=unit))
    return vals


def deg_list(text, what):
    return number_list(text, what, -MAX_ANGLE, MAX_ANGLE, " deg")


def positive(name, value):
    if not (math.isfinite(value) and value > 0):
        raise UsageError(f"--{name} must be a positive number (got {value})")


def non_negative(name, value):
    if not (math.isfinite(value) and value >= 0):
        raise UsageError(f"--{name} must be >= 0 (got {value})")


def firing_phases(tdc, order, strokes):
    """Firing TDC crank angles (deg) per cylinder from the TDC angles in [0, 360) and the order."""
    n = len(tdc)
    cycle = 720.0 if strokes == 4 else 360.0
    phase = [None] * n
    first = order[0] - 1
    phase[first] = tdc[first]
    prev = phase[first]
    for c in order[1:]:
        j = c - 1
        target = prev + cycle / n
        cands = [tdc[j] + 360.0 * k for k in range(-1, 4)]
        cands = [a for a in cands if a > prev + 1e-9 and a < phase[first] + cycle - 1e-9]
        if strokes == 2:
            # one TDC per cycle: the one after the first firing.
            cands = [a for a in cands if a >= phase[first]]
        if not cands:
            raise UsageError(
                f"--order: cylinder {c} has no top dead centre between the previous firing "
                f"({prev:g} deg) and the end of the cycle ({phase[first] + cycle:g} deg)")
        best = min(cands, key=lambda a: (abs(a - target), a))
        phase[j] = best
        prev = best
    return phase


def preset_name(text):
    """--preset: a name of PRESETS; an earlier name is refused with its new one."""
    if text in RENAMED:
        raise argparse.ArgumentTypeError(f"preset '{text}' is now called '{RENAMED[text]}' (the name mechgen_balance uses)")
    if text not in PRESETS:
        raise argparse.ArgumentTypeError(f"no preset '{text}'; presets are {', '.join(sorted(PRESETS))}")
    return text


def build(args, argv):
    preset = PRESETS[args.preset]
    throws = deg_list(args.throws, "throws") if args.throws else list(preset[0])
    banks = deg_list(args.banks, "banks") if args.banks else list(preset[1])
    if args.v_angle is not None:
        if args.preset not in V_PRESETS:
            raise UsageError("--v-angle applies to the " + ", ".join(V_PRESETS) + " presets only")
        if not (0 < args.v_angle < 180):
            raise UsageError(f"--v-angle must be in (0, 180) deg (got {args.v_angle})")
        half = args.v_angle / 2
        banks = [half if b > 0 else -half for b in banks]
    n = len(throws)
    if len(banks) != n:
        raise UsageError(f"--banks: {len(banks)} angles for {n} cylinders (--throws)")
    if args.order:
        try:
            order = [int(v) for v in args.order.replace("-", ",").split(",")]
            if any(abs(v) > 1000 for v in order):
                raise ValueError
        except ValueError:
            raise UsageError(f"--order: cylinder numbers like 1-3-4-2, got '{args.order}'")
    else:
        order = list(preset[2]) if len(preset[2]) == n else list(range(1, n + 1))
    if sorted(order) != list(range(1, n + 1)):
        raise UsageError(f"--order: a permutation of the cylinders 1..{n}, got {args.order or order}")
    if n > 16:
        raise UsageError(f"at most 16 cylinders (got {n})")
    for name, opt in (("bore", "bore"), ("stroke", "stroke"), ("rod_length", "rod-length"),
                      ("m_rod", "m-rod"), ("l_G", "l-G"), ("J_rod", "J-rod"), ("m_pis", "m-pis"),
                      ("m_crank", "m-crank"), ("J_fly", "J-fly")):
        positive(opt, getattr(args, name))
    for name, opt in (("T_load", "T-load"), ("c_load", "c-load")):
        non_negative(opt, getattr(args, name))
    if not math.isfinite(args.offset):
        raise UsageError("--offset must be finite")
    r = args.stroke / 2
    l = args.rod_length
    e = args.offset
    if not (l > r + abs(e)):
        raise UsageError(f"--rod-length ({l:g}) must exceed the crank radius ({r:g}, half the stroke) "
                         f"plus |offset| ({abs(e):g}): else the crank cannot turn")
    if not (args.l_G < l):
        raise UsageError(f"--l-G ({args.l_G:g}) must be less than the rod length ({l:g})")
    if args.z:
        z = number_list(args.z, "z", -MAX_LENGTH, MAX_LENGTH, " m")
        if len(z) != n:
            raise UsageError(f"--z: {len(z)} positions for {n} cylinders")
    else:
        z = [args.pitch * j for j in range(n)]
    delta = math.degrees(math.asin(e / (l + r)))
    tdc = [((b - g + delta) % 360.0 + 360.0) % 360.0 for g, b in zip(throws, banks)]
    tdc = [0.0 if abs(a - 360.0) < 1e-9 else a for a in tdc]
    phases = firing_phases(tdc, order, args.strokes)
    cycle = 720 if args.strokes == 4 else 360
    name = args.name or f"engine_{args.preset}"
    if not name.isidentifier() or "__" in name or name.endswith("_"):
        raise UsageError(f"--name '{name}' is not a C++ identifier without '__' or a trailing '_'")

    out = []
    w = out.append
    w(f"# Made by: tools/make_engine.py {shlex.join(argv)}")
    w("# Do not edit by hand: change the command and run it again (tests/engine checks the copy).")
    w(f"name: {name}")
    kind = f"{n}-cylinder {args.preset}" if n > 1 else "single-cylinder"
    w(f"title: Reciprocating engine, {kind}, {args.strokes}-stroke (tools/make_engine.py)")
    w("description: |")
    w(f"  Preset {args.preset}: {n} cylinder{'s' if n > 1 else ''} on one crankshaft (Paul 6.8, DYREC). Crank O at the")
    w("  origin (input theta_crank, CCW +) with one pin B_j per cylinder at radius r and throw angle")
    w("  gamma_j; rod_j from B_j to the wrist pin C_j (length l, centre of mass l_G from B_j);")
    w("  piston_j on the cylinder axis at bank angle beta_j through e n_j (offset e), slide")
    w("  s_slide_j outward from the crank. Throws (deg): " + ", ".join(f"{g:g}" for g in throws) + ";")
    w("  banks (deg): " + ", ".join(f"{b:g}" for b in banks) + "; firing order " +
      "-".join(str(c) for c in order) + "; firing TDC")
    w("  phases (deg): " + ", ".join(f"{p:g}" for p in phases) + f" over a {cycle} deg cycle.")
    w("  Gas: load p_gas_j A on piston j along its axis away from the head (p_gas_j gauge, Pa,")
    w("  set at run time; the engine tool adds the gas torque of a pressure law instead).")
    w("  Load torque -(T_load + c_load theta_crank_dot) on the crank. Gravity off. Units: m, kg, N, s.")
    w("parameters:")
    w(f"  bore:    {{value: {fmt(args.bore)}, doc: \"cylinder bore (m)\"}}")
    w(f"  r:       {{value: {fmt(r)}, doc: \"crank radius (m), half the stroke\"}}")
    w(f"  l:       {{value: {fmt(l)}, doc: \"connecting rod length B-C (m)\"}}")
    w(f"  e:       {{value: {fmt(e)}, doc: \"cylinder offset, desaxe (m): the axis passes e from O\"}}")
    w(f"  m_rod:   {{value: {fmt(args.m_rod)}, doc: \"connecting rod mass (kg)\"}}")
    w(f"  l_G:     {{value: {fmt(args.l_G)}, doc: \"rod centre of mass from the crank pin B (m)\"}}")
    w(f"  J_rod:   {{value: {fmt(args.J_rod)}, doc: \"rod moment of inertia about its centre of mass (kg m^2)\"}}")
    w(f"  m_pis:   {{value: {fmt(args.m_pis)}, doc: \"piston mass with pin and rings (kg)\"}}")
    w(f"  m_crank: {{value: {fmt(args.m_crank)}, doc: \"crankshaft mass (kg), centre of mass on the axis O\"}}")
    w(f"  J_fly:   {{value: {fmt(args.J_fly)}, doc: \"crankshaft with flywheel, moment of inertia about O (kg m^2)\"}}")
    w(f"  strokes: {{value: {fmt(args.strokes)}, doc: \"2 or 4: the cycle is 360 or 720 deg of crank angle\"}}")
    w(f"  T_load:  {{value: {fmt(args.T_load)}, doc: \"constant load torque on the crank (N m)\"}}")
    w(f"  c_load:  {{value: {fmt(args.c_load)}, doc: \"viscous load on the crank (N m s/rad)\"}}")
    w("  A_pis:   {derived: \"Pi*bore^2/4\", doc: \"piston area (m^2)\"}")
    for j in range(n):
        k = j + 1
        w(f"  gamma_{k}: {{value: {fmt(math.radians(throws[j]))}, doc: \"throw of cylinder {k}: "
          f"crank angle of its pin in the crank's frame (rad; {throws[j]:g} deg)\"}}")
        w(f"  beta_{k}:  {{value: {fmt(math.radians(banks[j]))}, doc: \"bank angle of cylinder {k}'s "
          f"axis (rad; {banks[j]:g} deg)\"}}")
        w(f"  phase_{k}: {{value: {fmt(math.radians(phases[j]))}, doc: \"crank angle of cylinder {k}'s "
          f"firing TDC (rad; {phases[j]:g} deg)\"}}")
        w(f"  z_{k}:     {{value: {fmt(z[j])}, doc: \"axial position of cylinder {k} along the crankshaft (m; for the rocking couples, mechgen/machines/engine/couples.h)\"}}")
        w(f"  p_gas_{k}: {{value: 0.0, doc: \"gas gauge pressure on piston {k} (Pa), set at run time\"}}")
    w("links:")
    pts = ", ".join(f"S_{j + 1}: [-e*sin(beta_{j + 1}), e*cos(beta_{j + 1})]" for j in range(n))
    w(f"  ground: {{ground: true, points: {{O: [0, 0], {pts}}}}}")
    pins = ", ".join(f"B_{j + 1}: [r*cos(gamma_{j + 1}), r*sin(gamma_{j + 1})]" for j in range(n))
    w(f"  crank: {{points: {{O: [0, 0], {pins}}}, mass: m_crank, center: [0, 0], inertia: J_fly}}")
    for j in range(n):
        k = j + 1
        w(f"  rod_{k}: {{points: {{B: [0, 0], C: [l, 0]}}, mass: m_rod, center: [l_G, 0], inertia: J_rod}}")
        w(f"  piston_{k}: {{points: {{C: [0, 0]}}, mass: m_pis, center: [0, 0]}}")
    w("joints:")
    w("  O: {revolute: [ground.O, crank.O]}")
    for j in range(n):
        k = j + 1
        w(f"  B_{k}: {{revolute: [crank.B_{k}, rod_{k}.B]}}")
        w(f"  C_{k}: {{revolute: [rod_{k}.C, piston_{k}.C]}}")
        w(f"  slide_{k}: {{prismatic: {{guide: ground.S_{k}, slider: piston_{k}.C, angle: beta_{k}}}}}")
    w("inputs:")
    w(f"  - {{joint: O, range: [0, {cycle}*deg]}}")
    w("loads:")
    w("  load: {torque: -(T_load + c_load*theta_crank_dot), on: crank}")
    for j in range(n):
        k = j + 1
        w(f"  gas_{k}: {{force: [-p_gas_{k}*A_pis*cos(beta_{k}), -p_gas_{k}*A_pis*sin(beta_{k})], at: piston_{k}.C}}")
    if args.design:
        # The design sensitivities (issue 27) of the engine's kinematics and masses: the
        # engine tool's flywheel --design differentiates its energy loop by them.
        w("design: [r, l, e, m_rod, l_G, J_rod, m_pis]")
    w("outputs:")
    w("  quantities: [K, L, scene, forces, potential, dynamics, shaking]")
    w("  points: [" + ", ".join(f"piston_{j + 1}.C" for j in range(n)) + "]")
    reac = ["O"] + [f"B_{j + 1}" for j in range(n)] + [f"C_{j + 1}" for j in range(n)] + \
        [f"slide_{j + 1}" for j in range(n)]
    w("  reactions: [" + ", ".join(reac) + "]")
    w("assembly:")
    w("  theta_crank: 0")
    for j in range(n):
        k = j + 1
        g, b = math.radians(throws[j]), math.radians(banks[j])
        bu, bn = r * math.cos(g - b), r * math.sin(g - b)
        s = bu + math.sqrt(l * l - (e - bn) ** 2)
        rod = b + math.atan2(e - bn, s - bu)
        w(f"  theta_rod_{k}: {fmt(round(rod, 12))}")
        w(f"  s_slide_{k}: {fmt(round(s, 12))}")
    return "\n".join(out) + "\n"


def main(argv):
    p = argparse.ArgumentParser(
        prog="make_engine.py",
        description="Prints a mechgen model (YAML) of a single-crankshaft reciprocating engine.")
    p.add_argument("--preset", required=True, type=preset_name, metavar="{" + ",".join(sorted(PRESETS)) + "}",
                   help="the layout, named as in mechgen_balance")
    p.add_argument("--name", help="model name (default engine_<preset>)")
    p.add_argument("--throws", help="throw angles gamma_j of the crank pins (deg, comma-separated)")
    p.add_argument("--banks", help="bank angles beta_j of the cylinder axes (deg, comma-separated)")
    p.add_argument("--v-angle", type=numeric("--v-angle", 0, 180, True, True, " deg"), help="V angle (deg) for " + ", ".join(V_PRESETS))
    p.add_argument("--order", help="firing order, e.g. 1-3-4-2")
    p.add_argument("--strokes", type=int, default=4, help="2 or 4 (default 4)")
    p.add_argument("--bore", type=numeric("--bore", 0, MAX_LENGTH, True, unit=" m"), default=0.086, help="bore (m; default 0.086)")
    p.add_argument("--stroke", type=numeric("--stroke", 0, MAX_LENGTH, True, unit=" m"), default=0.086, help="stroke 2 r (m; default 0.086)")
    p.add_argument("--rod-length", dest="rod_length", type=numeric("--rod-length", 0, MAX_LENGTH, True, unit=" m"), default=0.145,
                   help="connecting rod length l (m; default 0.145)")
    p.add_argument("--offset", type=numeric("--offset", -MAX_LENGTH, MAX_LENGTH, unit=" m"), default=0.0, help="cylinder offset e (m; default 0)")
    p.add_argument("--m-rod", dest="m_rod", type=numeric("--m-rod", 0, MAX_MASS, True, unit=" kg"), default=0.55, help="rod mass (kg)")
    p.add_argument("--l-G", dest="l_G", type=numeric("--l-G", 0, MAX_LENGTH, True, unit=" m"), default=0.038,
                   help="rod centre of mass from the crank pin (m)")
    p.add_argument("--J-rod", dest="J_rod", type=numeric("--J-rod", 0, MAX_MASS, True, unit=" kg m^2"), default=0.0018,
                   help="rod moment of inertia about its centre of mass (kg m^2)")
    p.add_argument("--m-pis", dest="m_pis", type=numeric("--m-pis", 0, MAX_MASS, True, unit=" kg"), default=0.45, help="piston mass (kg)")
    p.add_argument("--m-crank", dest="m_crank", type=numeric("--m-crank", 0, MAX_MASS, True, unit=" kg"), default=8.0, help="crankshaft mass (kg)")
    p.add_argument("--J-fly", dest="J_fly", type=numeric("--J-fly", 0, MAX_MASS, True, unit=" kg m^2"), default=0.15,
                   help="crankshaft and flywheel inertia about O (kg m^2)")
    p.add_argument("--T-load", dest="T_load", type=numeric("--T-load", 0, MAX_LOAD, unit=" N m"), default=0.0, help="load torque (N m)")
    p.add_argument("--c-load", dest="c_load", type=numeric("--c-load", 0, MAX_LOAD, unit=" N m s/rad"), default=0.0, help="viscous load (N m s/rad)")
    p.add_argument("--pitch", type=numeric("--pitch", -MAX_LENGTH, MAX_LENGTH, unit=" m"), default=0.095, help="cylinder pitch along the shaft (m)")
    p.add_argument("--z", help="axial positions z_j (m, comma-separated) instead of --pitch")
    p.add_argument("--design", action="store_true",
                   help="add a design section (r, l, e, m_rod, l_G, J_rod, m_pis): the design "
                        "sensitivities of the engine tool's flywheel --design")

    def error(message):
        raise UsageError(message)

    p.error = error
    try:
        args = p.parse_args(argv)
        if args.strokes not in (2, 4):
            raise UsageError(f"--strokes must be 2 or 4 (got {args.strokes})")
        text = build(args, argv)
    except UsageError as exc:
        sys.stderr.write(f"make_engine.py: error: {exc}\n")
        return 2
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
