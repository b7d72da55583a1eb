# Generates tests/files/bad/*.toml (run from anywhere: python3 tests/files/generate-bad.py): each a valid pendulum with one thing wrong; the first line
# says where the error must point (line:column of a marker chosen by hand) and what it says.
import os
BASE = '''version = 1
id = "bad_pendulum"
gravity = "g"

[[parameters]]
name = "g"
value = 9.81

[[parameters]]
name = "l"
value = 1.0
domain = "positive"

[[coordinates]]
name = "theta"
kind = "angle"
initial = 0.3

[[bodies]]
name = "bob"
mass = 1.0
x = "l*sin(theta)"
y = "-l*cos(theta)"
'''
GRAPH = '''version = 1
id = "bad_graph"

[graph]
gravity = 9.81

[[graph.bodies]]
name = "rod"
mass = 1.0
inertia = 0.0833

[[graph.joints]]
name = "theta"
kind = "revolute"
parent = "ground"
child = "rod"
parent_anchor = [0.0, 0.0]
child_anchor = [0.0, 0.5]

[initial]
q = [0.3]
qdot = [0.0]
'''
# name: (base, [(old, new)], marker, occurrence, offset, message)
cases = {
 "unclosed_parenthesis": (BASE, [('x = "l*sin(theta)"', 'x = "l*sin(theta"')], '"l*sin(theta"', 1, 12, "expected `,` or `)`"),
 "unknown_name": (BASE, [('cos(theta)', 'cos(thta)')], 'thta', 1, 0, "unknown name `thta`"),
 "unknown_function": (BASE, [('sin(theta)', 'sine(theta)')], 'sine', 1, 0, "unknown function `sine`"),
 "wrong_arity": (BASE, [('sin(theta)', 'atan2(theta)')], 'atan2', 1, 0, "takes 2 arguments"),
 "rate_in_position": (BASE, [('sin(theta)', 'sin(theta_dot)')], 'theta_dot', 1, 0, "cannot appear in a position"),
 "missing_body_field": (BASE, [('y = "-l*cos(theta)"\n', '')], '[[bodies]]', 1, 0, "missing field `y`"),
 "coordinate_moves_nothing": (BASE, [('[[bodies]]', '[[coordinates]]\nname = "phi"\nkind = "angle"\n\n[[bodies]]')], '"phi"', 1, 0, "no body moves with the coordinate `phi`"),
 "loop_cannot_close": (BASE, [('[[coordinates]]\nname = "theta"\nkind = "angle"\ninitial = 0.3\n', '[[coordinates]]\nname = "theta"\nkind = "angle"\ninitial = 0.3\n\n[[coordinates]]\nname = "s"\nkind = "length"\n\n[[constraints]]\nname = "rod"\nresidual = "s^2 + 1"\n'), ('y = "-l*cos(theta)"', 'y = "-l*cos(theta) - s"')], '"rod"', 1, 0, "rod"),
 "duplicate_name": (BASE, [('name = "l"\nvalue = 1.0', 'name = "g"\nvalue = 1.0')], '"g"', 3, 0, "`g` is declared twice"),
 "nan_value": (BASE, [('value = 1.0', 'value = nan')], 'nan', 1, 0, "must be finite"),
 "beyond_f64": (BASE, [('value = 1.0', 'value = 1e400')], '1e400', 1, 0, ""),
 "beyond_f64_in_expression": (BASE, [('x = "l*sin(theta)"', 'x = "1e400*sin(theta)"')], '1e400', 1, 0, "beyond the range"),
 "outside_domain": (BASE, [('value = 1.0', 'value = -1.0')], '-1.0', 1, 0, "must be positive"),
 "unknown_key": (BASE, [('gravity = "g"', 'gravty = "g"')], 'gravty', 1, 0, "unknown field `gravty`"),
 "unknown_kind": (BASE, [('kind = "angle"', 'kind = "angel"')], '"angel"', 1, 0, "unknown variant `angel`"),
 "wrong_version": (BASE, [('version = 1', 'version = 2')], '2', 1, 0, "version 2"),
 "bad_id": (BASE, [('id = "bad_pendulum"', 'id = "bad pendulum"')], '"bad pendulum"', 1, 0, "cannot be a scene id"),
 "id_of_a_built_in_scene": (BASE, [('id = "bad_pendulum"', 'id = "double_pendulum"')], '"double_pendulum"', 1, 0, "exists already"),
 "bodies_and_lagrangian": (BASE, [('gravity = "g"\n', 'lagrangian = "theta_dot^2/2"\n')], '"bob"', 1, 0, "bodies or a Lagrangian, not both"),
 "no_bodies": (BASE, [(BASE[BASE.index('[[bodies]]'):], '')], '"bad_pendulum"', 1, 0, "neither bodies nor a Lagrangian"),
 "unicode_minus": (BASE, [('y = "-l*cos(theta)"', 'y = "−l*cos(theta)"')], '−', 1, 0, "unexpected character `−`"),
 "implicit_product": (BASE, [('x = "l*sin(theta)"', 'x = "2l*sin(theta)"')], 'l*sin', 1, 0, "expected an operator"),
 "empty_expression": (BASE, [('x = "l*sin(theta)"', 'x = ""')], '""', 1, 1, "empty expression"),
 "force_on_unknown_coordinate": (BASE, [('', ''), ], None, 1, 0, None),
 "bound_without_side": (BASE, [('', '')], None, 1, 0, None),
 "negative_mass": (BASE, [('mass = 1.0', 'mass = -1.0')], '-1.0', 1, 0, "negative"),
 "coordinate_in_mass": (BASE, [('mass = 1.0', 'mass = "2*theta"')], 'theta"', 2, 0, "changes with the motion"),
 "time_in_inertia": (BASE, [('mass = 1.0', 'mass = 1.0\ninertia = "t"')], '"t"', 1, 1, "changes with the motion"),
 "toml_unterminated_string": (BASE, [('x = "l*sin(theta)"', 'x = "l*sin(theta)')], '"l*sin(theta)\n', 1, 13, ""),
 "duplicate_key": (BASE, [('y = "-l*cos(theta)"', 'y = "-l*cos(theta)"\ny = "0"')], 'y = "0"', 1, 0, "duplicate key"),
 "infinite_constant": (BASE, [('mass = 1.0', 'mass = "1/0"')], '1/0', 1, 0, "not a finite number"),
 "nan_initial_value": (BASE, [('initial = 0.3', 'initial = "ln(-1)"')], 'ln(-1)', 1, 0, "not a finite number"),
 "function_as_parameter_name": (BASE, [('name = "l"', 'name = "sin"'), ('l*sin(theta)', 'sin(theta)'), ('-l*cos', '-cos')], '"sin"', 1, 0, "cannot name a parameter"),
 "initial_in_coordinates_form": (BASE, [('', '')], None, 1, 0, None),
 "graph_joint_to_missing_body": (GRAPH, [('child = "rod"', 'child = "rodd"')], '"rodd"', 1, 0, "rodd"),
 "graph_without_initial_state": (GRAPH, [('[initial]\nq = [0.3]\nqdot = [0.0]\n', '')], '[graph]', 1, 0, "needs its initial state"),
 "graph_initial_state_of_wrong_size": (GRAPH, [('q = [0.3]\nqdot = [0.0]', 'q = [0.3, 0.1]\nqdot = [0.0, 0.0]')], '[initial]', 1, 0, "initial state"),
 "graph_with_coordinates_form_key": (GRAPH, [('id = "bad_graph"\n', 'id = "bad_graph"\npotential = "0"\n')], '"0"', 1, 0, "has no `potential`"),
 "graph_unknown_joint_kind": (GRAPH, [('kind = "revolute"', 'kind = "revolut"')], '"revolut"', 1, 0, "unknown variant `revolut`"),
}
extra = {
 "force_on_unknown_coordinate": BASE + '\n[[forces]]\ncoordinate = "thet"\nforce = "-theta_dot"\n',
 "bound_without_side": BASE + '\n[[region]]\nquantity = "theta"\n',
 "initial_in_coordinates_form": BASE + '\n[initial]\nq = [0.3]\n',
}
extra_marks = {
 "force_on_unknown_coordinate": ('"thet"', 1, 0, "no coordinate `thet`"),
 "bound_without_side": ('"theta"', 2, 0, "needs one of `above` and `below`"),
 "initial_in_coordinates_form": ('[initial]', 1, 0, "belongs to the joint-graph form"),
}
out = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'bad')
for f in os.listdir(out):
    if f.endswith('.toml') and f not in ('empty.toml', 'binary.toml'):
        os.remove(os.path.join(out, f))
for i, (name, (base, reps, marker, occ, off, msg)) in enumerate(sorted(cases.items())):
    if name in extra:
        text = extra[name]; marker, occ, off, msg = extra_marks[name]
    else:
        text = base
        for old, new in reps:
            assert old in text, (name, old)
            text = text.replace(old, new, 1)
    pos = -1
    for _ in range(occ):
        pos = text.index(marker, pos + 1)
    pos += off
    before = text[:pos]
    line = before.count('\n') + 2  # the expectation line comes first
    col = len(before.split('\n')[-1]) + 1
    header = f'# expect {line}:{col} {msg}\n'
    open(os.path.join(out, name + '.toml'), 'w').write(header + text)
open(os.path.join(out, 'empty.toml'), 'w').write('')
open(os.path.join(out, 'binary.toml'), 'wb').write(bytes([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0xff, 0xfe, 0x00, 0x01]))
print(len(os.listdir(out)))
