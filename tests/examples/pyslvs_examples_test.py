#!/usr/bin/env python3
"""The example mechanisms of Pyslvs (another open linkage tool), written as mechgen models in
tests/examples/pyslvs/, checked against that tool's own data without compiling anything.

Usage: pyslvs_examples_test.py MECHGEN MAKE_REFERENCE MODEL.yaml WORKDIR

1. `mechgen generate MODEL` must accept the model (mobility, the reach check over the inputs'
   ranges, change points noted, not refused).
2. `make_reference MODEL` (tests/reference: the generator's front end gives Phi, then damped
   Newton and continuation in 50-digit CLN, nothing of the emitted code) gives every joint
   point of every link at the inputs' grid over their whole range: 8 steps of a full turn
   for one input, a 5 x 5 grid for two.
3. Those positions are checked against the example's data below, transcribed from Pyslvs's
   example list (joint type, slider angle A in degrees, drawn position P[x, y], the links it
   joins, the input pairs (base joint, driven joint)); nothing of it is read from the model:
   - at the drawn input (q = 0: each link's frame is the drawing's) every joint is where
     Pyslvs draws it, to half a unit of the last decimal Pyslvs gives;
   - at every row the loops close: the links meeting at a joint agree on where it is, a pin
     in a slot (RP) lies on the slot's line (through the slot link's point at A plus that
     link's turn), a slider (P) lies on its guide's line and turns with the guide; every link
     keeps its drawn shape (the distances between its joints);
   - the inputs are Pyslvs's: q is the turn of the line from the base joint to the driven
     joint from its drawn direction (or, for a driven slot, the pin's travel along it);
   - a one-input full turn visits its whole range (the crank turns fully), and the parallel
     linkage stays a parallelogram (its coupler keeps its drawn direction) through the change
     points at 90 and 270 deg from the drawing.
"""
import math
import os
import subprocess
import sys

# Pyslvs's example list (pyslvs/examples.py), the data only: name -> (Pyslvs's name, input
# pairs, joints (type, A [deg] or None, x, y, links)); x and y as Pyslvs spells them.
EXAMPLES = {
    'arm': ('Arm', [(0, 1), (0, 2)], [
        ('R', None, '-34.25', '-20.625', ['ground', 'L1', 'L2']),
        ('R', None, '29.75', '77.375', ['L2', 'L5', 'L6']),
        ('R', None, '-54.0', '10.875', ['L1', 'L3']),
        ('R', None, '-86.25', '-3.125', ['ground', 'L4']),
        ('R', None, '-7.25', '94.625', ['L4', 'L5']),
        ('R', None, '57.0', '110.875', ['L5', 'L8']),
        ('R', None, '126.5', '56.125', ['L7', 'L8']),
        ('R', None, '114.5', '35.625', ['L6', 'L7']),
        ('R', None, '7.0', '131.125', ['L3', 'L6']),
        ('R', None, '163.5', '47.875', ['L7']),
    ]),
    'ball_lifter_double': ('Ball lifter (Double)', [(0, 1)], [
        ('R', None, '10.2', '10.4', ['ground', 'L1']),
        ('R', None, '7.44', '20.01', ['L1', 'L2', 'L6']),
        ('R', None, '-10.52', '11.21', ['L2', 'L3']),
        ('R', None, '-28.48', '2.42', ['L2', 'L4']),
        ('R', None, '-6.6', '0.0', ['ground', 'L3']),
        ('R', None, '-12.8', '0.0', ['ground', 'L5']),
        ('R', None, '-22.61', '12.64', ['L4', 'L5']),
        ('R', None, '-56.1', '6.78', ['L4']),
        ('R', None, '43.78', '20.17', ['ground', 'L7']),
        ('R', None, '15.02', '40.85', ['L6', 'L7']),
        ('R', None, '22.0284', '59.8421', ['L6', 'L8']),
        ('R', None, '23.8', '0.0', ['ground', 'L9']),
        ('R', None, '35.64', '40.55', ['L8', 'L9']),
        ('R', None, '8.73', '80.39', ['L8']),
    ]),
    'ball_lifter_triple': ('Ball lifter (Triple)', [(0, 1)], [
        ('R', None, '10.2', '10.4', ['ground', 'L1']),
        ('R', None, '7.44', '20.01', ['L1', 'L2', 'L6', 'L10']),
        ('R', None, '-10.52', '11.21', ['L2', 'L3']),
        ('R', None, '-28.48', '2.42', ['L2', 'L4']),
        ('R', None, '-6.6', '0.0', ['ground', 'L3']),
        ('R', None, '-12.8', '0.0', ['ground', 'L5']),
        ('R', None, '-19.11', '32.24', ['L4', 'L5']),
        ('R', None, '-64.12', '4.61', ['L4']),
        ('R', None, '43.78', '20.17', ['ground', 'L7']),
        ('R', None, '13.9', '38.46', ['L6', 'L7']),
        ('R', None, '21.05', '62.93', ['L6', 'L8']),
        ('R', None, '23.8', '0.0', ['ground', 'L9']),
        ('R', None, '39.15', '41.95', ['L8', 'L9']),
        ('R', None, '10.29', '92.17', ['L8']),
        ('R', None, '73.44', '61.74', ['L10', 'L11']),
        ('R', None, '63.67', '0.0', ['ground', 'L11']),
        ('R', None, '101.58', '72.34', ['L10', 'L12']),
        ('R', None, '92.30', '-1.63', ['L13', 'ground']),
        ('R', None, '111.74', '70.43', ['L12', 'L13']),
        ('R', None, '7.50', '93.44', ['L12']),
    ]),
    'crank_lifter': ('Crank lifter', [(0, 1)], [
        ('R', None, '-67.38', '36.13', ['ground', 'L1']),
        ('R', None, '-68.925', '55.925', ['L1', 'L2']),
        ('RP', '0.0', '11.88', '0.0', ['ground', 'L2', 'L3']),
        ('R', None, '50.775', '24.7908', ['L3', 'L4']),
        ('R', None, '80.375', '8.625', ['ground', 'L4']),
        ('R', None, '109.1972', '63.8805', ['L3', 'L5']),
        ('RP', '0.0', '0.82', '64.42', ['L5', 'L4']),
    ]),
    'crank_rocker': ('Crank rocker', [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '12.92', '32.53', ['L1', 'L2']),
        ('R', None, '73.28', '67.97', ['L2', 'L3']),
        ('R', None, '33.3', '66.95', ['L2']),
        ('R', None, '90.0', '0.0', ['ground', 'L3']),
    ]),
    'crank_slider_p_joint': ('Crank slider (P joint)', [(0, 1)], [
        ('R', None, '-33.625', '-19.625', ['ground', 'L1']),
        ('R', None, '-48.375', '12.125', ['L1', 'L3']),
        ('R', None, '17.125', '33.875', ['L2', 'L3']),
        ('P', '30.0', '51.38', '-12.63', ['ground', 'L2']),
        ('R', None, '50.35', '53.117', ['L2', 'L5']),
        ('R', None, '143.455', '65.967', ['L4', 'L5']),
        ('R', None, '99.244', '20.447', ['ground', 'L4']),
    ]),
    'crank_slider_rp_joint': ('Crank slider (RP joint)', [(0, 1)], [
        ('R', None, '-67.38', '36.13', ['ground', 'L1']),
        ('R', None, '-68.925', '55.925', ['L1', 'L2']),
        ('RP', '0.0', '11.88', '0.0', ['ground', 'L2', 'L3']),
        ('R', None, '50.775', '24.7908', ['L3', 'L4']),
        ('R', None, '74.375', '7.625', ['ground', 'L4']),
        ('R', None, '95.1972', '52.8805', ['L3']),
    ]),
    'crank_slider_three_bar': ('Crank slider (Three bar)', [(0, 1)], [
        ('R', None, '-30.0', '-10.0', ['ground', 'L1']),
        ('R', None, '-9.9986', '4.999', ['L1', 'L2']),
        ('RP', '0.0', '65.0', '-45.0', ['L2', 'ground']),
    ]),
    'horse_leg': ('Horse leg', [(0, 3)], [
        ('R', None, '49', '-75', ['ground', 'link_1']),
        ('R', None, '100', '-69', ['ground', 'link_2']),
        ('R', None, '139', '-63', ['link_5', 'ground']),
        ('R', None, '52', '-97', ['link_1', 'link_3']),
        ('R', None, '108', '-81', ['link_3', 'link_4']),
        ('R', None, '108', '-107', ['link_2', 'link_3']),
        ('R', None, '156', '-114', ['link_4', 'link_5']),
        ('R', None, '193', '-149', ['link_5', 'link_7']),
        ('R', None, '109', '-127', ['link_2', 'link_6']),
        ('R', None, '204', '-169', ['link_6', 'link_7']),
        ('R', None, '230', '-219', ['link_7']),
    ]),
    'inverted_slider': ('Inverted slider', [(0, 2)], [
        ('R', None, '0', '0', ['ground', 'L1']),
        ('R', None, '56', '0', ['ground', 'L3']),
        ('R', None, '7', '25', ['L1', 'L2']),
        ('P', '0.0', '59', '41', ['L3', 'L2']),
    ]),
    'jansens_linkage_single': ("Jansen's linkage (Single)", [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '9.61', '11.52', ['L1', 'L2', 'L4']),
        ('R', None, '-38.0', '-7.8', ['ground', 'L3', 'L5']),
        ('R', None, '-35.24', '33.61', ['L2', 'L3']),
        ('R', None, '-77.75', '-2.54', ['L3', 'L6']),
        ('R', None, '-20.1', '-42.79', ['L4', 'L5', 'L7']),
        ('R', None, '-56.05', '-35.42', ['L6', 'L7']),
        ('R', None, '-22.22', '-91.74', ['L7']),
    ]),
    'jansens_linkage_double': ("Jansen's linkage (Double)", [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '9.61', '11.52', ['L1', 'L2', 'L4', 'L8', 'L10']),
        ('R', None, '-38.0', '-7.8', ['ground', 'L3', 'L5']),
        ('R', None, '-35.24', '33.61', ['L2', 'L3']),
        ('R', None, '-77.75', '-2.54', ['L3', 'L6']),
        ('R', None, '-20.1', '-42.79', ['L4', 'L5', 'L7']),
        ('R', None, '-56.05', '-35.42', ['L6', 'L7']),
        ('R', None, '-22.22', '-91.74', ['L7']),
        ('R', None, '38.0', '-7.8', ['ground', 'L9', 'L11']),
        ('R', None, '56.28', '29.46', ['L8', 'L9']),
        ('R', None, '75.07', '-23.09', ['L9', 'L12']),
        ('R', None, '31.18', '-46.5', ['L10', 'L11', 'L13']),
        ('R', None, '64.84', '-61.13', ['L12', 'L13']),
        ('R', None, '4.79', '-87.79', ['L13']),
    ]),
    'parallel_linkage': ('Parallel Linkage', [(0, 2)], [
        ('R', None, '0', '0', ['ground', 'link_1']),
        ('R', None, '100', '0', ['ground', 'link_3']),
        ('R', None, '0', '100', ['link_1', 'link_2']),
        ('R', None, '100', '100', ['link_2', 'link_3']),
    ]),
    'slider_lifter': ('Slider lifter', [(0, 0)], [
        ('RP', '0.0', '0.0', '0.0', ['ground', 'L2']),
        ('R', None, '50.0', '0.0', ['ground', 'L1']),
        ('R', None, '25.0', '27.0', ['L1', 'L2']),
        ('R', None, '1.0', '54.0', ['L1']),
        ('R', None, '50.0', '53.0', ['L2']),
    ]),
    'stephenson_i': ('Stephenson I', [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '29.4258', '46.6507', ['L1', 'L5']),
        ('R', None, '10.7895', '114.378', ['L1', 'L2']),
        ('R', None, '73.75', '202.8125', ['L2', 'L3']),
        ('R', None, '146.25', '146.5625', ['L3', 'L4']),
        ('R', None, '105.25', '87.5625', ['L4', 'L5']),
        ('R', None, '113.75', '0.0', ['ground', 'L4']),
    ]),
    'stephenson_ii': ('Stephenson II', [(0, 1)], [
        ('R', None, '-45.0', '-15.5', ['ground', 'L1']),
        ('R', None, '-52.0', '25.5', ['L1', 'L2']),
        ('R', None, '-36.0', '76.25', ['L2', 'L5']),
        ('R', None, '-4.0', '3.0', ['L2', 'L4']),
        ('R', None, '29.0', '27.5', ['L3', 'L4']),
        ('R', None, '85.25', '-27.25', ['ground', 'L3']),
        ('R', None, '57.5', '77.0', ['L3', 'L5']),
    ]),
    'stephenson_iii': ('Stephenson III', [(0, 1)], [
        ('R', None, '0.25', '-0.625', ['ground', 'L1']),
        ('R', None, '15.375', '41.125', ['L1', 'L2']),
        ('R', None, '61.375', '95.125', ['L2', 'L3']),
        ('R', None, '102.875', '84.375', ['L3', 'L4']),
        ('R', None, '117.125', '23.375', ['ground', 'L4']),
        ('R', None, '134.625', '119.875', ['L3', 'L5']),
        ('R', None, '138.875', '33.125', ['ground', 'L5']),
    ]),
    'stephenson_iii_slider': ('Stephenson III (slider)', [(0, 1)], [
        ('R', None, '0', '0', ['ground', 'link_1']),
        ('R', None, '-24', '20', ['link_1', 'link_3']),
        ('R', None, '80', '-58', ['ground', 'link_2']),
        ('R', None, '44', '16', ['link_2', 'link_3']),
        ('R', None, '68', '36', ['link_3', 'link_4']),
        ('RP', '0.0', '136', '28', ['ground', 'link_4']),
    ]),
    'ten_folds_levers': ("Ten Fold's levers", [(0, 2)], [
        ('R', None, '17.0', '-19.0', ['ground', 'L2']),
        ('R', None, '17.0', '-107.0833', ['ground', 'L3', 'L4']),
        ('R', None, '42.0', '-45.25', ['L1', 'L2']),
        ('R', None, '75.5', '-45.0', ['L1', 'L3', 'L7', 'L9']),
        ('R', None, '108.8819', '-45.0', ['L8', 'L9']),
        ('R', None, '160.5', '-44.75', ['L9', 'L11']),
        ('R', None, '75.25', '-80.0', ['L2', 'L6', 'L8']),
        ('R', None, '132.8819', '-21.5972', ['L8', 'L10']),
        ('R', None, '185.4653', '-21.1736', ['L10', 'L11']),
        ('R', None, '108.7917', '-80.2917', ['L6', 'L7']),
        ('R', None, '76.3043', '-104.3817', ['L4', 'L5']),
        ('R', None, '132.026', '-104.8377', ['L5', 'L7']),
        ('R', None, '221.6968', '-20.8773', ['L10']),
    ]),
    'watt_i': ('Watt I', [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '-18.6154', '41.3846', ['L1', 'L2']),
        ('R', None, '29.0', '116.5', ['L2', 'L3']),
        ('R', None, '38.0', '69.0', ['L2', 'L5']),
        ('R', None, '95.0', '143.0', ['L3', 'L4']),
        ('R', None, '122.0', '76.5', ['L4', 'L5']),
        ('R', None, '64.0', '0.0', ['ground', 'L5']),
    ]),
    'watt_ii': ('Watt II', [(0, 1)], [
        ('R', None, '0.0', '0.0', ['ground', 'L1']),
        ('R', None, '-5.3333', '36.0', ['L1', 'L2']),
        ('R', None, '42.6667', '48.3333', ['L2', 'L3']),
        ('R', None, '60.0', '1.3333', ['ground', 'L3']),
        ('R', None, '79.0', '71.3333', ['L3', 'L4']),
        ('R', None, '113.6667', '36.0', ['L4', 'L5']),
        ('R', None, '87.0', '-17.0', ['ground', 'L5']),
    ]),
    'watt_ii_slider': ('Watt II (slider)', [(0, 1)], [
        ('R', None, '0', '0', ['ground', 'link_3']),
        ('R', None, '-4.1011', '-49.6944', ['link_1', 'link_3']),
        ('R', None, '-151.1537', '-50.2107', ['link_1', 'link_2']),
        ('RP', '45.0', '-139.0458', '20.2296', ['ground', 'link_2']),
        ('P', '45.0', '-47.356', '-102.562', ['link_1', 'link_4']),
        ('R', None, '15.3065', '-161.8204', ['ground', 'link_4']),
    ]),
}

FULL_TURN_EXCEPTIONS = {'arm', 'ten_folds_levers', 'slider_lifter'}  # ranges: see the models


def decimals(text):
    return len(text.split('.')[1]) if '.' in text else 0


def read_reference(path):
    head = {}
    rows = []
    columns = None
    with open(path) as f:
        for line in f:
            line = line.rstrip('\n')
            if line.startswith('#'):
                body = line[1:].strip()
                for key in ('q:', 'points:'):
                    if body.startswith(key):
                        head[key[:-1]] = body[len(key):].split()
                if body.startswith('nq='):
                    head['nq'] = int(body.split()[0][3:])
            elif columns is None:
                columns = line.split(',')
            elif line:
                rows.append(dict(zip(columns, (float(v) for v in line.split(',')))))
    return head, rows


def angle_of(v):
    return math.atan2(v[1], v[0])


def wrap(a):
    return (a + math.pi) % (2 * math.pi) - math.pi


def main():
    mechgen, make_reference, model_path, work = sys.argv[1:5]
    key = os.path.splitext(os.path.basename(model_path))[0]
    title, inputs, joints = EXAMPLES[key]
    os.makedirs(work, exist_ok=True)
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    gen = subprocess.run([mechgen, 'generate', model_path, '-o', work], capture_output=True, text=True)
    sys.stderr.write(gen.stderr)
    if gen.returncode != 0:
        print(f'{key}: mechgen generate refused the model (exit {gen.returncode})')
        return 1
    csv = os.path.join(work, key + '.csv')
    # 8 steps of a full turn; 11 for the parallel linkage, whose rows and 1-degree sub-steps then
    # miss its change points (90 and 270 deg from the drawing), where K is undefined.
    steps = 4 if len(inputs) == 2 else 11 if key == 'parallel_linkage' else 8
    options = ['--steps', str(steps)]
    if key == 'parallel_linkage':
        options += ['--follow-change-points', 'yes']
    ref = subprocess.run([make_reference, model_path, csv] + options, capture_output=True, text=True)
    sys.stderr.write(ref.stderr)
    if ref.returncode != 0:
        print(f'{key}: make_reference failed (exit {ref.returncode})')
        return 1
    head, rows = read_reference(csv)
    check(head.get('nq') == len(inputs), f"mobility: {head.get('nq')} inputs, Pyslvs drives {len(inputs)}")

    drawn = [(float(x), float(y)) for (_, _, x, y, _) in joints]
    scale = max(math.hypot(a[0] - b[0], a[1] - b[1]) for a in drawn for b in drawn)
    tol = 1e-9 * scale
    index = {}  # (link, joint) -> column index of its point
    for m, name in enumerate(head['points']):
        link, point = name.split('.')
        index[(link, int(point[1:]))] = m
    links = {}
    for i, (_, _, _, _, ls) in enumerate(joints):
        for link in ls:
            links.setdefault(link, []).append(i)
    for link, js in links.items():
        if link != 'ground':
            for i in js:
                check((link, i) in index, f'no output point {link}.J{i}')
    if failures:
        print('\n'.join(f'{key}: FAIL {f}' for f in failures))
        return 1

    def position(row, link, i):
        if link == 'ground':
            return drawn[i]
        m = index[(link, i)]
        return (row[f'rP_0_{m}'], row[f'rP_1_{m}'])

    def turn(row, link):
        """The link's rotation from the drawing (0 for the ground)."""
        if link == 'ground':
            return 0.0
        a, b = links[link][0], links[link][1]
        pa, pb = position(row, link, a), position(row, link, b)
        return wrap(angle_of((pb[0] - pa[0], pb[1] - pa[1])) -
                    angle_of((drawn[b][0] - drawn[a][0], drawn[b][1] - drawn[a][1])))

    drawn_rows = [r for r in rows if all(r[f'q_{j}'] == 0 for j in range(len(inputs)))]
    check(len(drawn_rows) == 1, f'{len(drawn_rows)} rows at the drawn input q = 0')
    worst_drawn = 0.0
    for row in drawn_rows:
        for (link, i) in index:
            p = position(row, link, i)
            _, _, xs, ys, _ = joints[i]
            for c, text in ((p[0], xs), (p[1], ys)):
                err = abs(c - float(text))
                worst_drawn = max(worst_drawn, err)
                check(err <= 0.5 * 10.0 ** -decimals(text),
                      f'{link}.J{i} at the drawn input: {p}, Pyslvs draws ({xs}, {ys})')

    worst = 0.0
    for row in rows:
        q = [row[f'q_{j}'] for j in range(len(inputs))]
        where = 'q = (' + ', '.join(f'{v:.6g}' if b == d else f'{math.degrees(v):.6g} deg'
                                    for v, (b, d) in zip(q, inputs)) + ')'
        for i, (kind, a, _, _, ls) in enumerate(joints):
            if kind == 'R':
                for link in ls[1:]:
                    p, r = position(row, ls[0], i), position(row, link, i)
                    d = math.hypot(p[0] - r[0], p[1] - r[1])
                    worst = max(worst, d)
                    check(d <= tol, f'J{i}: {ls[0]} and {link} {d:.3g} apart at {where}')
            else:
                g = position(row, ls[0], i)
                u = math.radians(float(a)) + turn(row, ls[0])
                for link in ls[1:]:
                    p = position(row, link, i)
                    off = -(p[0] - g[0]) * math.sin(u) + (p[1] - g[1]) * math.cos(u)
                    worst = max(worst, abs(off))
                    check(abs(off) <= tol, f'J{i} ({kind}): {link} is {off:.3g} off the line of {ls[0]} at {where}')
                    if kind == 'P':
                        dt = abs(wrap(turn(row, link) - turn(row, ls[0])))
                        check(dt <= 1e-9, f'J{i} (P): {link} turns {dt:.3g} rad from its guide {ls[0]} at {where}')
        for link, js in links.items():
            for x in js:
                for y in js:
                    if x < y:
                        px, py = position(row, link, x), position(row, link, y)
                        d = math.hypot(px[0] - py[0], px[1] - py[1])
                        d0 = math.hypot(drawn[x][0] - drawn[y][0], drawn[x][1] - drawn[y][1])
                        worst = max(worst, abs(d - d0))
                        check(abs(d - d0) <= tol, f'{link}: |J{x}J{y}| = {d:.12g}, drawn {d0:.12g} at {where}')
        for j, (b, d) in enumerate(inputs):
            if b == d:  # a driven slot: q is the pin's travel along it
                kind, a, _, _, ls = joints[b]
                p = position(row, ls[1], b)
                u = math.radians(float(a))
                s = (p[0] - drawn[b][0]) * math.cos(u) + (p[1] - drawn[b][1]) * math.sin(u)
                check(abs(s - q[j]) <= tol, f'input {j}: slide {s:.12g} != q at {where}')
            else:
                link = [l for l in joints[b][4] if l in joints[d][4] and l != 'ground'][0]
                pb, pd = position(row, link, b), position(row, link, d)
                t = wrap(angle_of((pd[0] - pb[0], pd[1] - pb[1])) -
                         angle_of((drawn[d][0] - drawn[b][0], drawn[d][1] - drawn[b][1])))
                check(abs(wrap(t - q[j])) <= 1e-9, f'input {j}: J{b}->J{d} turned {t:.12g} != q at {where}')
        if key == 'parallel_linkage':
            t = turn(row, 'link_2')
            check(abs(t) <= 1e-9, f'the coupler turned {t:.3g} rad at {where}: off the parallelogram')

    if len(inputs) == 1 and key not in FULL_TURN_EXCEPTIONS:
        qs = sorted(r['q_0'] for r in rows)
        check(len(qs) == steps and qs[0] == 0 and abs(qs[-1] - 2 * math.pi * (steps - 1) / steps) < 1e-12,
              f'a full turn in {steps} steps expected, got q = {qs}')
    if key == 'parallel_linkage':
        check('2 change point(s) passed' in ref.stderr, 'make_reference did not pass the two change points')
    if failures:
        print('\n'.join(f'{key}: FAIL {f}' for f in failures[:20]))
        return 1
    print(f'{key} (Pyslvs "{title}"): {len(rows)} configurations; at the drawn input every joint within '
          f'{worst_drawn:.2g} of Pyslvs; joints, slots and link shapes within {worst:.2g} (scale {scale:.4g})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
