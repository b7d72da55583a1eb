//! A joint graph written out in the coordinates form: the coordinates the reduced model chose
//! (one per free tree joint), every body's pose as an expression in them (forward kinematics
//! along the spanning tree), the loop-closing joints' residuals as constraints, springs as the
//! potential, and dampers, torques and forces as generalized forces `Q_i = Σ F · ∂p/∂q_i`.
//!
//! The conventions are those of [`GraphMechanism`] (joint values, anchors, the order and sign of
//! the constraint rows), so that the file gives the graph's `q̈` and multipliers; the test suite
//! checks it on every shipped graph. The file is plain text the reader parses as any other, and
//! the equations `lagrange eom` prints for a joint graph are this file's.

use crate::expr::Function;
use lagrange::graph::{ForceElement, GROUND, GraphMechanism, JointGraph, JointType, Point, Profile};
use lagrange::tree::AngleReference;
use lagrange::{Error, State};

/// An expression being composed: a sum keeps its terms flat with their coefficients, so like
/// terms merge (`0.1 cos θ + 0.1 cos θ` is `0.2 cos θ`) and zeros and ones fall away.
#[derive(Clone, Debug, PartialEq)]
enum X {
    Num(f64),
    Name(String),
    /// `Σ c_k x_k`: at least two terms, or one with a coefficient other than 1; no term is a
    /// number (the constant is the term `c · 1`) or a sum.
    Sum(Vec<(f64, X)>),
    Mul(Box<X>, Box<X>),
    Div(Box<X>, Box<X>),
    /// A power with a constant exponent.
    Pow(Box<X>, f64),
    Call(Function, Box<X>),
}

use X::Num;

const ONE: X = Num(1.0);

fn name(n: &str) -> X {
    X::Name(n.to_string())
}

fn is(x: &X, v: f64) -> bool {
    matches!(x, Num(n) if *n == v)
}

/// `x` as `Σ c_k x_k`.
fn terms(x: X) -> Vec<(f64, X)> {
    match x {
        Num(0.0) => Vec::new(),
        Num(v) => vec![(v, ONE)],
        X::Sum(terms) => terms,
        other => vec![(1.0, other)],
    }
}

/// `Σ c_k x_k`, like terms merged.
fn sum(list: Vec<(f64, X)>) -> X {
    let mut merged: Vec<(f64, X)> = Vec::with_capacity(list.len());
    for (c, x) in list {
        match merged.iter_mut().find(|(_, y)| *y == x) {
            Some(term) => term.0 += c,
            None => merged.push((c, x)),
        }
    }
    merged.retain(|(c, _)| *c != 0.0);
    match merged.len() {
        0 => Num(0.0),
        1 if merged[0].1 == ONE => Num(merged[0].0),
        1 if merged[0].0 == 1.0 => merged.pop().expect("one term").1,
        _ => X::Sum(merged),
    }
}

fn scale(x: X, c: f64) -> X {
    sum(terms(x).into_iter().map(|(k, t)| (k * c, t)).collect())
}

fn neg(a: X) -> X {
    scale(a, -1.0)
}

fn add(a: X, b: X) -> X {
    let mut list = terms(a);
    list.extend(terms(b));
    sum(list)
}

fn sub(a: X, b: X) -> X {
    add(a, neg(b))
}

/// A product's coefficient and the rest: `(c, x)` for `c x`.
fn coefficient(x: X) -> (f64, X) {
    match x {
        Num(v) => (v, ONE),
        X::Sum(mut terms) if terms.len() == 1 => terms.pop().expect("one term"),
        other => (1.0, other),
    }
}

fn mul(a: X, b: X) -> X {
    let ((ca, a), (cb, b)) = (coefficient(a), coefficient(b));
    let product = match (a, b) {
        (a, b) if a == ONE => b,
        (a, b) if b == ONE => a,
        (a, b) => X::Mul(Box::new(a), Box::new(b)),
    };
    scale(product, ca * cb)
}

fn div(a: X, b: X) -> X {
    let ((ca, a), (cb, b)) = (coefficient(a), coefficient(b));
    if ca == 0.0 {
        return Num(0.0);
    }
    let quotient = if b == ONE { a } else { X::Div(Box::new(a), Box::new(b)) };
    scale(quotient, ca / cb)
}

fn pow(a: X, k: f64) -> X {
    match a {
        _ if k == 1.0 => a,
        Num(v) => Num(v.powf(k)),
        a => X::Pow(Box::new(a), k),
    }
}

fn call(f: Function, a: X) -> X {
    // Only the exact values fold (sin 0, cos 0): a folded cos 0.3 would be a 17-digit decimal
    // in the file and in the printed equations.
    match (f, &a) {
        (Function::Sin | Function::Tan | Function::Sinh | Function::Asin | Function::Atan, Num(v)) if *v == 0.0 => {
            Num(0.0)
        }
        (Function::Cos | Function::Cosh | Function::Exp, Num(v)) if *v == 0.0 => ONE,
        _ => X::Call(f, Box::new(a)),
    }
}

fn sin(a: X) -> X {
    call(Function::Sin, a)
}

fn cos(a: X) -> X {
    call(Function::Cos, a)
}

/// `∂x/∂v`.
fn diff(x: &X, v: &str) -> X {
    match x {
        Num(_) => Num(0.0),
        X::Name(n) => Num(if n == v { 1.0 } else { 0.0 }),
        X::Sum(terms) => sum(terms
            .iter()
            .map(|(c, t)| (*c, diff(t, v)))
            .flat_map(|(c, d)| self::terms(d).into_iter().map(move |(k, t)| (c * k, t)))
            .collect()),
        X::Mul(a, b) => add(mul(diff(a, v), (**b).clone()), mul((**a).clone(), diff(b, v))),
        X::Div(a, b) => {
            let top = sub(mul(diff(a, v), (**b).clone()), mul((**a).clone(), diff(b, v)));
            div(top, pow((**b).clone(), 2.0))
        }
        X::Pow(a, k) => mul(mul(Num(*k), pow((**a).clone(), k - 1.0)), diff(a, v)),
        X::Call(f, a) => {
            let (a, da) = ((**a).clone(), diff(a, v));
            if is(&da, 0.0) {
                return Num(0.0);
            }
            let outer = match f {
                Function::Sin => cos(a),
                Function::Cos => neg(sin(a)),
                Function::Sqrt => div(Num(0.5), call(Function::Sqrt, a)),
                // The composition writes sin, cos and sqrt (and `ln`, `atan` … nowhere).
                _ => unreachable!("unfold composes sin, cos and sqrt only"),
            };
            mul(outer, da)
        }
    }
}

/// Precedence in the text's grammar: sum 1, product 2, power 4, atom 5.
fn precedence(x: &X) -> u8 {
    match x {
        X::Sum(terms) if terms.len() > 1 => 1,
        X::Sum(_) | X::Mul(..) | X::Div(..) => 2,
        Num(v) if *v < 0.0 => 2,
        X::Pow(..) => 4,
        _ => 5,
    }
}

fn number(v: f64) -> String {
    // The shortest text that reads back to the same float.
    let text = format!("{v:?}");
    text.strip_suffix(".0").map_or(text.clone(), str::to_string)
}

fn wrap(x: &X, at_least: u8) -> String {
    if precedence(x) < at_least { format!("({})", text(x)) } else { text(x) }
}

/// The expression as scene-file text, parenthesized where the grammar needs it.
fn text(x: &X) -> String {
    match x {
        Num(v) => number(*v),
        X::Name(n) => n.clone(),
        X::Sum(terms) => {
            let mut out = String::new();
            for (k, (c, t)) in terms.iter().enumerate() {
                let sign = if *c < 0.0 { "-" } else { "+" };
                match k {
                    0 if *c < 0.0 => out.push('-'),
                    0 => {}
                    _ => out.push_str(&format!(" {sign} ")),
                }
                let c = c.abs();
                out.push_str(&match (c == 1.0, *t == ONE) {
                    (_, true) => number(c),
                    (true, false) => wrap(t, 2),
                    (false, false) => format!("{}*{}", number(c), wrap(t, 2)),
                });
            }
            out
        }
        X::Mul(a, b) => format!("{}*{}", wrap(a, 2), wrap(b, 4)),
        X::Div(a, b) => format!("{}/{}", wrap(a, 2), wrap(b, 4)),
        X::Pow(a, k) => format!("{}^{}", wrap(a, 5), if *k < 0.0 { format!("({})", number(*k)) } else { number(*k) }),
        X::Call(f, a) => format!("{}({})", f.name(), text(a)),
    }
}

/// A body's pose `(x, y, φ)`.
#[derive(Clone, Debug)]
struct Pose {
    x: X,
    y: X,
    angle: X,
}

impl Pose {
    fn ground() -> Self {
        Self { x: Num(0.0), y: Num(0.0), angle: Num(0.0) }
    }
}

fn rotate(angle: &X, v: [X; 2]) -> [X; 2] {
    let [a, b] = v;
    let (c, s) = (cos(angle.clone()), sin(angle.clone()));
    [sub(mul(c.clone(), a.clone()), mul(s.clone(), b.clone())), add(mul(s, a), mul(c, b))]
}

fn numbers(v: [f64; 2]) -> [X; 2] {
    [Num(v[0]), Num(v[1])]
}

/// `c + r t + A sin(ω t + φ₀)`.
fn profile(p: &Profile) -> X {
    let mut value = add(Num(p.constant), mul(Num(p.rate), name("t")));
    if p.amplitude != 0.0 {
        value = add(value, mul(Num(p.amplitude), sin(add(mul(Num(p.frequency), name("t")), Num(p.phase)))));
    }
    value
}

/// A name the expression language reads: letters (any alphabet), digits, `_` and `'`, not
/// starting with a digit; anything else becomes `_`.
fn identifier(raw: &str) -> String {
    let mut out: String =
        raw.chars().map(|c| if c.is_alphanumeric() || c == '_' || c == '\'' { c } else { '_' }).collect();
    if !out.starts_with(|c: char| c.is_alphabetic() || c == '_') {
        out.insert_str(0, "q_");
    }
    out
}

struct Unfolded<'a> {
    mechanism: &'a GraphMechanism,
    /// The coordinates' names in the file, in the model's order.
    coordinates: Vec<String>,
    /// Each body's pose.
    poses: Vec<Pose>,
}

impl Unfolded<'_> {
    fn graph(&self) -> &JointGraph {
        self.mechanism.graph()
    }

    /// Tree joint `j`'s value: its coordinate, its drive `q(t)`, `ratio · source + offset`, or 0.
    fn tree_value(&self, j: usize) -> X {
        if let Some(i) = self.mechanism.coordinate_joints().iter().position(|&k| k == j) {
            return name(&self.coordinates[i]);
        }
        if let Some(p) = self.mechanism.drive(j) {
            return profile(&p);
        }
        if let Some((source, ratio)) = self.mechanism.coupling(j) {
            return add(mul(Num(ratio), self.tree_value(source)), Num(self.offset(j)));
        }
        Num(0.0)
    }

    fn offset(&self, j: usize) -> f64 {
        let joint = &self.graph().joints[j].name;
        self.graph().couplings.iter().find(|c| &c.joint == joint).map_or(0.0, |c| c.offset)
    }

    fn pose(&self, body: Option<usize>) -> Pose {
        body.map_or_else(Pose::ground, |b| self.poses[b].clone())
    }

    /// The pose of the body tree joint `j` places, from the one it hangs from (`known`).
    fn place(&self, j: usize, known: &Pose, v: X) -> Pose {
        let spec = &self.graph().joints[j];
        let sign = spec.sense.sign();
        let (turn, slide) = match spec.kind {
            JointType::Revolute => (mul(Num(sign), v.clone()), None),
            JointType::Prismatic { axis } => (Num(0.0), Some(axis)),
            JointType::Fixed { angle } => (Num(angle), None),
        };
        let slid = |anchor: [f64; 2]| -> [X; 2] {
            match slide {
                Some(axis) => [
                    add(mul(v.clone(), Num(axis[0])), Num(anchor[0])),
                    add(mul(v.clone(), Num(axis[1])), Num(anchor[1])),
                ],
                None => numbers(anchor),
            }
        };
        if !self.mechanism.is_reversed(j) {
            let angle = if spec.kind == JointType::Revolute && spec.angle == AngleReference::World {
                turn
            } else {
                add(known.angle.clone(), turn)
            };
            let [ax, ay] = rotate(&known.angle, slid(spec.parent_anchor));
            let [cx, cy] = rotate(&angle, numbers(spec.child_anchor));
            Pose { x: sub(add(known.x.clone(), ax), cx), y: sub(add(known.y.clone(), ay), cy), angle }
        } else {
            let angle = sub(known.angle.clone(), turn);
            let [cx, cy] = rotate(&known.angle, numbers(spec.child_anchor));
            let [ax, ay] = rotate(&angle, slid(spec.parent_anchor));
            Pose { x: sub(add(known.x.clone(), cx), ax), y: sub(add(known.y.clone(), cy), ay), angle }
        }
    }

    /// The world position of `at` on `body` (`None`: the ground).
    fn point(&self, body: Option<usize>, at: [f64; 2]) -> [X; 2] {
        match body {
            None => numbers(at),
            Some(b) => {
                let pose = &self.poses[b];
                let [dx, dy] = rotate(&pose.angle, numbers(at));
                [add(pose.x.clone(), dx), add(pose.y.clone(), dy)]
            }
        }
    }

    fn body(&self, name: &str) -> Option<usize> {
        if name == GROUND { None } else { self.mechanism.body_index(name) }
    }

    fn at(&self, p: &Point) -> [X; 2] {
        self.point(self.body(&p.body), p.at)
    }

    /// Joint `j`'s value from its bodies' poses (the tree value for a tree joint).
    fn value(&self, j: usize) -> X {
        if self.mechanism.in_tree(j) {
            return self.tree_value(j);
        }
        let spec = &self.graph().joints[j];
        let (p, c) = self.mechanism.joint_ends(j);
        let (parent, child) = (self.pose(p), self.pose(c));
        match spec.kind {
            JointType::Revolute => {
                let relative = match spec.angle {
                    AngleReference::Parent => sub(child.angle, parent.angle),
                    AngleReference::World => child.angle,
                };
                mul(Num(spec.sense.sign()), relative)
            }
            JointType::Prismatic { axis } => {
                let (a, c) = (self.point(p, spec.parent_anchor), self.point(c, spec.child_anchor));
                let [ux, uy] = rotate(&parent.angle, numbers(axis));
                let [a0, a1] = a;
                let [c0, c1] = c;
                add(mul(sub(c0, a0), ux), mul(sub(c1, a1), uy))
            }
            JointType::Fixed { .. } => Num(0.0),
        }
    }

    /// Loop-closing joint `j`'s constraint rows, as the reduced model numbers and signs them.
    fn rows(&self, j: usize) -> Vec<X> {
        let spec = &self.graph().joints[j];
        let (p, c) = self.mechanism.joint_ends(j);
        let (parent, child) = (self.pose(p), self.pose(c));
        let ([a0, a1], [c0, c1]) = (self.point(p, spec.parent_anchor), self.point(c, spec.child_anchor));
        let mut rows = match spec.kind {
            JointType::Revolute => vec![sub(a0, c0), sub(a1, c1)],
            JointType::Prismatic { axis } => {
                let [ux, uy] = rotate(&parent.angle, numbers(axis));
                vec![sub(mul(sub(c0, a0), uy), mul(sub(c1, a1), ux)), sub(child.angle, parent.angle)]
            }
            JointType::Fixed { angle } => {
                vec![sub(a0, c0), sub(a1, c1), sub(sub(child.angle, parent.angle), Num(angle))]
            }
        };
        if let Some(drive) = self.mechanism.drive(j) {
            rows.push(sub(self.value(j), profile(&drive)));
        } else if let Some((source, ratio)) = self.mechanism.coupling(j) {
            let coupled = add(mul(Num(ratio), self.tree_value(source)), Num(self.offset(j)));
            rows.push(sub(self.value(j), coupled));
        }
        rows
    }

    /// `ẋ = Σ_j ∂x/∂q_j q̇_j + ∂x/∂t`.
    fn rate(&self, x: &X) -> X {
        let mut out = diff(x, "t");
        for q in &self.coordinates {
            out = add(out, mul(diff(x, q), name(&format!("{q}_dot"))));
        }
        out
    }
}

/// The parameters of the file: `g`, and each body's mass and inertia that are not zero.
struct Parameter {
    name: String,
    value: f64,
    unit: &'static str,
    domain: &'static str,
    description: String,
}

/// The coordinates-form text of `graph` started at `initial`, with the header `header` (the
/// lines from `version` to `reference`/`horizon`).
pub(crate) fn coordinates_text(graph: &JointGraph, initial: &State, header: &str) -> Result<String, Error> {
    if initial.t != 0.0 {
        return Err(Error::InvalidParameter {
            name: "t".into(),
            value: initial.t,
            why: "the coordinates form starts its motion at t = 0".into(),
        });
    }
    let mechanism = GraphMechanism::new(graph.clone())?;
    let mut used: Vec<String> = Vec::new();
    let mut unique = |raw: &str| {
        let base = identifier(raw);
        let mut candidate = base.clone();
        let mut k = 2;
        while used.contains(&candidate) || ["t", "pi", "g"].contains(&candidate.as_str()) {
            candidate = format!("{base}_{k}");
            k += 1;
        }
        used.push(candidate.clone());
        candidate
    };
    let coordinates: Vec<String> =
        mechanism.coordinate_joints().iter().map(|&j| unique(&graph.joints[j].name)).collect();
    let mut unfolded = Unfolded { mechanism: &mechanism, coordinates, poses: vec![Pose::ground(); graph.bodies.len()] };
    for &(j, b) in mechanism.tree_order() {
        let (parent, child) = mechanism.joint_ends(j);
        let known = unfolded.pose(if mechanism.is_reversed(j) { child } else { parent });
        unfolded.poses[b] = unfolded.place(j, &known, unfolded.tree_value(j));
    }

    let mut parameters = vec![Parameter {
        name: "g".into(),
        value: graph.gravity,
        unit: "m/s²",
        domain: "finite",
        description: "gravitational acceleration along −y".into(),
    }];
    let mut masses = Vec::new();
    for body in &graph.bodies {
        let mut property = |symbol: &str, value: f64, unit: &'static str, what: &str| {
            if value == 0.0 {
                return "0".to_string();
            }
            let name = unique(&format!("{symbol}_{}", body.name));
            parameters.push(Parameter {
                name: name.clone(),
                value,
                unit,
                domain: "non_negative",
                description: format!("{what} of `{}`", body.name),
            });
            name
        };
        let mass = property("m", body.mass, "kg", "mass");
        let inertia = property("I", body.inertia, "kg m²", "moment of inertia about the centre of mass");
        masses.push((mass, inertia));
    }

    let mut potential = Num(0.0);
    let mut forces = vec![Num(0.0); unfolded.coordinates.len()];
    let generalized = |forces: &mut [X], along: &dyn Fn(&str) -> X| {
        for (f, q) in forces.iter_mut().zip(&unfolded.coordinates) {
            *f = add(f.clone(), along(q));
        }
    };
    for element in &graph.forces {
        match element {
            ForceElement::Spring { a, b, stiffness, rest_length } => {
                let ([ax, ay], [bx, by]) = (unfolded.at(a), unfolded.at(b));
                let squared = add(pow(sub(bx, ax), 2.0), pow(sub(by, ay), 2.0));
                let stretch = if *rest_length == 0.0 {
                    squared
                } else {
                    pow(sub(call(Function::Sqrt, squared), Num(*rest_length)), 2.0)
                };
                potential = add(potential, mul(Num(0.5 * stiffness), stretch));
            }
            ForceElement::JointSpring { joint, stiffness, rest } => {
                let j = graph.joints.iter().position(|k| &k.name == joint).expect("a checked joint");
                potential = add(potential, mul(Num(0.5 * stiffness), pow(sub(unfolded.value(j), Num(*rest)), 2.0)));
            }
            ForceElement::Damper { a, b, coefficient } => {
                // Q_i = −c L̇ ∂L/∂q_i, L = |d|, d = p_b − p_a: −c (d·ḋ)(d·∂d/∂q_i)/(d·d).
                let ([ax, ay], [bx, by]) = (unfolded.at(a), unfolded.at(b));
                let (dx, dy) = (sub(bx, ax), sub(by, ay));
                let along_d = |ex: X, ey: X| add(mul(dx.clone(), ex), mul(dy.clone(), ey));
                let rate = along_d(unfolded.rate(&dx), unfolded.rate(&dy));
                let squared = along_d(dx.clone(), dy.clone());
                generalized(&mut forces, &|q| {
                    let lever = along_d(diff(&dx, q), diff(&dy, q));
                    if is(&lever, 0.0) {
                        return Num(0.0);
                    }
                    neg(div(mul(mul(Num(*coefficient), rate.clone()), lever), squared.clone()))
                });
            }
            ForceElement::JointDamper { joint, coefficient } => {
                let j = graph.joints.iter().position(|k| &k.name == joint).expect("a checked joint");
                let v = unfolded.value(j);
                let rate = unfolded.rate(&v);
                generalized(&mut forces, &|q| neg(mul(mul(Num(*coefficient), rate.clone()), diff(&v, q))));
            }
            ForceElement::Torque { body, torque } => {
                let angle = unfolded.pose(unfolded.body(body)).angle;
                let tau = profile(torque);
                generalized(&mut forces, &|q| mul(tau.clone(), diff(&angle, q)));
            }
            ForceElement::Force { at, force } => {
                let [px, py] = unfolded.at(at);
                let (fx, fy) = (profile(&force[0]), profile(&force[1]));
                generalized(&mut forces, &|q| add(mul(fx.clone(), diff(&px, q)), mul(fy.clone(), diff(&py, q))));
            }
        }
    }

    // The file.
    let mut out = String::from(header);
    let line = |out: &mut String, text: String| {
        out.push_str(&text);
        out.push('\n');
    };
    let quoted = |s: &str| toml::Value::String(s.to_string()).to_string();
    line(&mut out, "gravity = \"g\"".into());
    if !is(&potential, 0.0) {
        line(&mut out, "# The springs.".into());
        line(&mut out, format!("potential = {}", quoted(&text(&potential))));
    }
    line(&mut out, "\n# Parameters: gravity and the bodies' masses and inertias.".into());
    for p in &parameters {
        line(&mut out, "\n[[parameters]]".into());
        line(&mut out, format!("name = {}", quoted(&p.name)));
        line(&mut out, format!("value = {}", toml::Value::Float(p.value)));
        line(&mut out, format!("unit = {}", quoted(p.unit)));
        line(&mut out, format!("domain = {}", quoted(p.domain)));
        line(&mut out, format!("description = {}", quoted(&p.description)));
    }
    line(&mut out, "\n# The coordinates: one per free joint of the spanning tree, named after it.".into());
    for (i, (q, &j)) in unfolded.coordinates.iter().zip(mechanism.coordinate_joints()).enumerate() {
        let kind = match graph.joints[j].kind {
            JointType::Prismatic { .. } => "length",
            _ => "angle",
        };
        line(&mut out, "\n[[coordinates]]".into());
        line(&mut out, format!("name = {}", quoted(q)));
        line(&mut out, format!("kind = \"{kind}\""));
        line(&mut out, format!("initial = {}", toml::Value::Float(initial.q[i])));
        line(&mut out, format!("rate = {}", toml::Value::Float(initial.qdot[i])));
    }
    line(&mut out, "\n# The bodies: each pose by forward kinematics along the spanning tree.".into());
    for (b, body) in graph.bodies.iter().enumerate() {
        let pose = &unfolded.poses[b];
        let (mass, inertia) = &masses[b];
        line(&mut out, "\n[[bodies]]".into());
        line(&mut out, format!("name = {}", quoted(&body.name)));
        line(&mut out, format!("mass = {}", quoted(mass)));
        line(&mut out, format!("inertia = {}", quoted(inertia)));
        for (key, x) in [("x", &pose.x), ("y", &pose.y), ("angle", &pose.angle)] {
            line(&mut out, format!("{key} = {}", quoted(&text(x))));
        }
    }
    let loaded: Vec<(usize, &X)> = forces.iter().enumerate().filter(|(_, f)| !is(f, 0.0)).collect();
    if !loaded.is_empty() {
        line(&mut out, "\n# Dampers, torques and forces: Q_i = Σ F · ∂p/∂q_i.".into());
    }
    for (i, f) in loaded {
        line(&mut out, "\n[[forces]]".into());
        line(&mut out, format!("coordinate = {}", quoted(&unfolded.coordinates[i])));
        line(&mut out, format!("force = {}", quoted(&text(f))));
    }
    let closing: Vec<usize> = (0..graph.joints.len()).filter(|&j| !mechanism.in_tree(j)).collect();
    if !closing.is_empty() {
        line(&mut out, "\n# The loop-closing joints.".into());
    }
    for j in closing {
        for (row, residual) in mechanism.joint_row_names(j).iter().zip(unfolded.rows(j)) {
            line(&mut out, "\n[[constraints]]".into());
            line(&mut out, format!("name = {}", quoted(row)));
            line(&mut out, format!("residual = {}", quoted(&text(&residual))));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_reads_back_with_the_grammar() {
        let (a, b) = (name("a"), name("b"));
        assert_eq!(text(&neg(add(a.clone(), b.clone()))), "-a - b");
        assert_eq!(text(&sub(a.clone(), sub(b.clone(), Num(1.0)))), "a - b + 1");
        assert_eq!(text(&mul(a.clone(), Num(-0.5))), "-0.5*a");
        assert_eq!(text(&mul(neg(a.clone()), add(a.clone(), b.clone()))), "-a*(a + b)");
        assert_eq!(text(&pow(neg(a.clone()), 2.0)), "(-a)^2");
        assert_eq!(text(&add(mul(cos(Num(0.0)), a.clone()), mul(sin(Num(0.0)), b.clone()))), "a");
        assert_eq!(text(&add(mul(Num(0.1), cos(a.clone())), mul(cos(a.clone()), Num(0.1)))), "0.2*cos(a)");
        assert_eq!(text(&div(a.clone(), mul(a.clone(), b.clone()))), "a/(a*b)");
        // d/da (a² sin a) = 2 a sin a + a² cos a.
        assert_eq!(text(&diff(&mul(pow(a.clone(), 2.0), sin(a)), "a")), "2*a*sin(a) + a^2*cos(a)");
    }
}
