//! The equations of a coordinates-form scene, derived symbolically from the file's
//! expressions and written as a textbook writes them: `T`, `V`, `L`, Lagrange's equations with
//! the accelerations on the left, the constraints with their multipliers, the momenta of
//! cyclic coordinates, the energy where it is conserved, and `q̈` where `M` is constant and
//! diagonal.
//!
//! `T = ½ Σ_b (m_b (ẋ_b² + ẏ_b²) + I_b φ̇_b²)`, `V = V_file + Σ_b m_b g y_b`, and for each
//! coordinate `d/dt ∂L/∂q̇_i − ∂L/∂q_i + Σ_k λ_k ∂Φ_k/∂q_i (+ Σ_k λ_k ∂ψ_k/∂q̇_i) = Q_i`, the
//! engine's `M q̈ + Gᵀ λ = f` (docs/method.md#constraints): the printed multipliers are the
//! engine's.

pub mod algebra;
mod present;
pub mod print;
pub mod text;

use crate::coordinates::{CoordinateForm, Located};
use crate::expr::{Ast, BinaryOp, Function};
use algebra::{Atom, Poly, Rational, Symbol, Unsupported};
use print::{Names, Style};
use serde::Serialize;

/// A formula in the three styles.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Formula {
    /// Unicode, as a textbook prints it.
    pub unicode: String,
    /// LaTeX.
    pub latex: String,
    /// The scene-file expression language (rates `x_dot`, accelerations `x_ddot`,
    /// multipliers `lambda1`, …), which [`crate::expr::parse`] reads back.
    pub plain: String,
}

/// An equation `left = right`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Equation {
    /// What it is (`θ`, the coordinate whose equation it is; a constraint's name).
    pub label: String,
    /// The left side.
    pub left: Formula,
    /// The right side.
    pub right: Formula,
}

/// A body's pose, as printed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BodyPose {
    /// The body's name.
    pub body: String,
    /// `x`.
    pub x: Formula,
    /// `y`.
    pub y: Formula,
    /// `φ`.
    pub angle: Formula,
}

/// Everything `lagrange eom` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Equations {
    /// The coordinates, as printed, with their kind.
    pub coordinates: Vec<(String, String)>,
    /// For a joint graph, the body poses its coordinates give (forward kinematics along the
    /// spanning tree); empty for the coordinates form, whose file writes them.
    pub poses: Vec<BodyPose>,
    /// Kinetic energy (none for a raw Lagrangian).
    pub kinetic: Option<Formula>,
    /// Potential energy, gravity included (none for a raw Lagrangian).
    pub potential: Option<Formula>,
    /// The Lagrangian.
    pub lagrangian: Formula,
    /// Lagrange's equations, one per coordinate, accelerations on the left.
    pub equations: Vec<Equation>,
    /// The constraints, `Φ_k = 0` and `ψ_k = 0`, with the symbol of each multiplier.
    pub constraints: Vec<Equation>,
    /// The momenta of cyclic coordinates, each conserved.
    pub conserved_momenta: Vec<Equation>,
    /// The energy function, where it is conserved.
    pub conserved_energy: Option<Equation>,
    /// `q̈` in closed form, where the mass matrix is constant (diagonal, or of up to three
    /// coordinates) and there are no constraints.
    pub accelerations: Vec<Equation>,
}

/// The symbol table: coordinates, rates, accelerations, `t`, `π`, parameters, multipliers.
struct Table {
    n: usize,
    parameters: Vec<String>,
    names: Names,
}

impl Table {
    fn q(&self, i: usize) -> Symbol {
        i as Symbol
    }
    fn rate(&self, i: usize) -> Symbol {
        (self.n + i) as Symbol
    }
    fn accel(&self, i: usize) -> Symbol {
        (2 * self.n + i) as Symbol
    }
    fn t(&self) -> Symbol {
        (3 * self.n) as Symbol
    }
    fn pi(&self) -> Symbol {
        (3 * self.n + 1) as Symbol
    }
    fn parameter(&self, k: usize) -> Symbol {
        (3 * self.n + 2 + k) as Symbol
    }
    fn multiplier(&self, k: usize) -> Symbol {
        (3 * self.n + 2 + self.parameters.len() + k) as Symbol
    }

    fn new(form: &CoordinateForm, symbols: &[String], multipliers: usize) -> Self {
        let n = form.coordinates.len();
        let mut names = Vec::new();
        let mut moving = Vec::new();
        for dots in 0..3 {
            for c in &form.coordinates {
                let (unicode, latex) = print::pretty(&c.name, dots);
                let plain = match dots {
                    0 => c.name.clone(),
                    1 => format!("{}_dot", c.name),
                    _ => format!("{}_ddot", c.name),
                };
                names.push([unicode, latex, plain]);
                moving.push(true);
            }
        }
        names.push(["t".into(), "t".into(), "t".into()]);
        moving.push(true);
        names.push(["π".into(), "\\pi".into(), "pi".into()]);
        moving.push(false);
        for (name, symbol) in form.parameters.iter().zip(symbols) {
            // Unicode as the file's symbol (`m₁`), LaTeX from the name (`m_{1}`).
            let (pretty, latex) = print::pretty(name, 0);
            let unicode = if symbol != name { symbol.clone() } else { pretty };
            names.push([unicode, latex, name.clone()]);
            moving.push(false);
        }
        for k in 0..multipliers {
            let (unicode, latex) = print::pretty(&format!("lambda{}", k + 1), 0);
            names.push([unicode, latex, format!("lambda{}", k + 1)]);
            moving.push(true);
        }
        Self { n, parameters: form.parameters.clone(), names: Names { names, moving, order: n } }
    }

    fn resolve(&self, name: &str) -> Result<Symbol, Unsupported> {
        if name == "t" {
            return Ok(self.t());
        }
        if name == "pi" {
            return Ok(self.pi());
        }
        if let Some(k) = self.parameters.iter().position(|p| p == name) {
            return Ok(self.parameter(k));
        }
        let coordinate = |n: &str| (0..self.n).find(|&i| self.names.names[i][2] == n);
        if let Some(i) = coordinate(name) {
            return Ok(self.q(i));
        }
        if let Some(i) = name.strip_suffix("_dot").and_then(coordinate) {
            return Ok(self.rate(i));
        }
        Err(Unsupported(format!("unknown name `{name}`")))
    }

    fn poly(&self, ast: &Ast) -> Result<Poly, Unsupported> {
        Ok(match ast {
            Ast::Number(v, _) => Poly::constant(Rational::from_f64(*v)?),
            Ast::Name(name, _) => Poly::sym(self.resolve(name)?),
            Ast::Neg(a, _) => self.poly(a)?.neg(),
            Ast::Binary(op, a, b, _) => {
                let (pa, pb) = (self.poly(a)?, self.poly(b)?);
                match op {
                    BinaryOp::Add => pa.add(&pb)?,
                    BinaryOp::Sub => pa.sub(&pb)?,
                    BinaryOp::Mul => pa.mul(&pb)?,
                    BinaryOp::Div => pa.mul(&pb.powi(-1)?)?,
                    BinaryOp::Pow => match pb.as_constant() {
                        Some(r) => pa.powr(r)?,
                        None => return Err(Unsupported("a power with a variable exponent".into())),
                    },
                }
            }
            Ast::Call(Function::Atan2, args, _) => {
                Poly::atom(Atom::Atan2(Box::new(self.poly(&args[0])?), Box::new(self.poly(&args[1])?)))
            }
            Ast::Call(f, args, _) => self.poly(&args[0])?.apply(*f)?,
        })
    }

    fn located(&self, e: Option<&Located>) -> Result<Poly, Unsupported> {
        e.map_or(Ok(Poly::zero()), |e| self.poly(&e.ast))
    }

    /// `d/dt f = Σ_j (∂f/∂q_j q̇_j + ∂f/∂q̇_j q̈_j) + ∂f/∂t`.
    fn time_derivative(&self, f: &Poly) -> Result<Poly, Unsupported> {
        let mut out = f.diff(self.t())?;
        for j in 0..self.n {
            out = out.add(&f.diff(self.q(j))?.mul(&Poly::sym(self.rate(j)))?)?;
            out = out.add(&f.diff(self.rate(j))?.mul(&Poly::sym(self.accel(j)))?)?;
        }
        Ok(out)
    }

    fn formula(&self, p: &Poly) -> Formula {
        Formula {
            unicode: print::write(p, &self.names, Style::Unicode),
            latex: print::write(p, &self.names, Style::Latex),
            plain: print::write(p, &self.names, Style::Plain),
        }
    }

    fn equation(&self, label: String, left: &Poly, right: &Poly) -> Equation {
        Equation { label, left: self.formula(left), right: self.formula(right) }
    }
}

/// Whether every body's pose is affine in the coordinates with constant coefficients and free
/// of `t` (so the mass matrix is constant): each `∂(x, y, φ)/∂q_i` is free of the coordinates
/// and of time. `false` where the derivation does not take an expression.
pub(crate) fn constant_mass_matrix(form: &CoordinateForm) -> bool {
    if form.lagrangian.is_some() {
        return false;
    }
    let names: Vec<String> = form.parameters.clone();
    let table = Table::new(form, &names, 0);
    let moving = |p: &Poly| p.contains(&|s| (s as usize) < table.n || s == table.t());
    form.bodies.iter().all(|b| {
        [Some(&b.x), Some(&b.y), b.angle.as_ref()].into_iter().flatten().all(|e| {
            table.poly(&e.ast).is_ok_and(|p| {
                !p.contains(&|s| s == table.t()) && (0..table.n).all(|i| p.diff(table.q(i)).is_ok_and(|d| !moving(&d)))
            })
        })
    })
}

/// Derive the equations of a coordinates-form file with the parameter symbols `symbols`.
pub(crate) fn derive(form: &CoordinateForm, symbols: &[String]) -> Result<Equations, Unsupported> {
    let (m, k) = (form.constraints.len(), form.velocity_constraints.len());
    let table = Table::new(form, symbols, m + k);
    let one_half = Rational::new(1, 2)?;
    let (kinetic, potential, lagrangian) = match &form.lagrangian {
        Some(l) => (None, None, table.poly(&l.ast)?),
        None => {
            let gravity = table.located(form.gravity.as_ref())?;
            let (mut t, mut v) = (Poly::zero(), table.located(form.potential.as_ref())?);
            for b in &form.bodies {
                let mass = table.poly(&b.mass.ast)?;
                let inertia = table.located(b.inertia.as_ref())?;
                let (x, y, angle) = (table.poly(&b.x.ast)?, table.poly(&b.y.ast)?, table.located(b.angle.as_ref())?);
                let (vx, vy, w) =
                    (table.time_derivative(&x)?, table.time_derivative(&y)?, table.time_derivative(&angle)?);
                let translation = mass.mul(&vx.mul(&vx)?.add(&vy.mul(&vy)?)?)?;
                t = t.add(&translation.add(&inertia.mul(&w.mul(&w)?)?)?.scale(one_half)?)?;
                v = v.add(&mass.mul(&gravity)?.mul(&y)?)?;
            }
            let (t, v) = (t.simplify()?, v.simplify()?);
            let l = t.sub(&v)?;
            (Some(t), Some(v), l)
        }
    };
    let lagrangian = lagrangian.simplify()?;
    // Printed forms: the potential's squares completed, their shifts factored in the equations.
    let moves = |s: Symbol| table.names.moving[s as usize];
    let mut presenter = present::Presenter::new((0..table.n).map(|i| table.q(i)).collect(), &moves);
    let potential_printed = potential.as_ref().map(|v| presenter.energy(v)).transpose()?;
    let constraints: Vec<Poly> = form.constraints.iter().map(|(_, c)| table.poly(&c.ast)).collect::<Result<_, _>>()?;
    let velocity: Vec<Poly> =
        form.velocity_constraints.iter().map(|(_, c)| table.poly(&c.ast)).collect::<Result<_, _>>()?;
    let mut forces = vec![Poly::zero(); table.n];
    for (i, f) in &form.forces {
        forces[*i] = forces[*i].add(&table.poly(&f.ast)?)?;
    }

    let mut equations = Vec::new();
    let mut mass_rows = Vec::new();
    let mut right_sides = Vec::new();
    let mut momenta = Vec::new();
    for i in 0..table.n {
        let momentum = lagrangian.diff(table.rate(i))?.simplify()?;
        let mut residual = table.time_derivative(&momentum)?.sub(&lagrangian.diff(table.q(i))?)?.sub(&forces[i])?;
        for (k, phi) in constraints.iter().enumerate() {
            residual = residual.add(&Poly::sym(table.multiplier(k)).mul(&phi.diff(table.q(i))?)?)?;
        }
        for (k, psi) in velocity.iter().enumerate() {
            residual = residual.add(&Poly::sym(table.multiplier(m + k)).mul(&psi.diff(table.rate(i))?)?)?;
        }
        let residual = residual.simplify()?;
        let mut left = Poly::zero();
        let mut row = Vec::new();
        for j in 0..table.n {
            let coefficient = residual.diff(table.accel(j))?.simplify()?;
            left = left.add(&coefficient.mul(&Poly::sym(table.accel(j)))?)?;
            row.push(coefficient);
        }
        let right = left.sub(&residual)?.simplify()?;
        equations.push(table.equation(table.names.names[i][0].clone(), &left, &presenter.force(&right)?));
        mass_rows.push(row);
        right_sides.push(right);
        momenta.push(momentum);
    }

    let involves = |p: &Poly, s: Symbol| p.contains(&|x| x == s);
    let mut conserved_momenta = Vec::new();
    for i in 0..table.n {
        let cyclic = !involves(&lagrangian, table.q(i))
            && forces[i].is_zero()
            && !constraints.iter().any(|c| involves(c, table.q(i)))
            && !velocity.iter().any(|c| involves(c, table.rate(i)) || involves(c, table.q(i)));
        if cyclic {
            let [unicode, latex, plain] = &table.names.names[i];
            let left = Formula {
                unicode: format!("p_{unicode}"),
                latex: format!("p_{{{latex}}}"),
                plain: format!("p_{plain}"),
            };
            conserved_momenta.push(Equation { label: unicode.clone(), left, right: table.formula(&momenta[i]) });
        }
    }
    let autonomous = !involves(&lagrangian, table.t())
        && forces.iter().all(Poly::is_zero)
        && !constraints.iter().chain(&velocity).any(|c| involves(c, table.t()));
    let conserved_energy = if autonomous {
        // h = Σ q̇_i ∂L/∂q̇_i − L (= T + V for bodies whose poses do not depend on t).
        let mut h = lagrangian.neg();
        for (i, p) in momenta.iter().enumerate() {
            h = h.add(&Poly::sym(table.rate(i)).mul(p)?)?;
        }
        let left = Formula { unicode: "E".into(), latex: "E".into(), plain: "E".into() };
        Some(Equation { label: "E".into(), left, right: table.formula(&presenter.energy(&h.simplify()?)?) })
    } else {
        None
    };

    // q̈ in closed form where the mass matrix is constant and there are no constraints: each
    // equation divided by its diagonal entry when M is diagonal, else Cramer's rule
    // q̈ = adj(M) f / det M (up to three coordinates).
    let moving = |p: &Poly| p.contains(&|s| table.names.moving[s as usize]);
    let mut accelerations = Vec::new();
    let constant = mass_rows.iter().flatten().all(|c| !moving(c));
    let diagonal =
        mass_rows.iter().enumerate().all(|(i, row)| row.iter().enumerate().all(|(j, c)| (i == j) != c.is_zero()));
    if m + k == 0 && constant && (diagonal || table.n <= 3) {
        let det = if diagonal { None } else { Some(determinant(&mass_rows)?.simplify()?) };
        for i in 0..table.n {
            let (numerator, denominator) = match &det {
                None => (right_sides[i].clone(), mass_rows[i][i].clone()),
                Some(det) => {
                    let mut numerator = Poly::zero();
                    for (j, f) in right_sides.iter().enumerate() {
                        numerator = numerator.add(&cofactor(&mass_rows, j, i)?.mul(f)?)?;
                    }
                    (numerator.simplify()?, det.clone())
                }
            };
            let (numerator, denominator) = cancel(&numerator, &denominator)?;
            let value = numerator.mul(&denominator.powi(-1)?)?;
            accelerations.push(table.equation(
                table.names.names[2 * table.n + i][0].clone(),
                &Poly::sym(table.accel(i)),
                &value.simplify()?,
            ));
        }
    }

    let mut constraint_equations = Vec::new();
    for (k, ((name, _), p)) in
        form.constraints.iter().chain(&form.velocity_constraints).zip(constraints.iter().chain(&velocity)).enumerate()
    {
        let label = format!("{name} ({})", table.names.names[table.multiplier(k) as usize][0]);
        constraint_equations.push(table.equation(label, &p.simplify()?, &Poly::zero()));
    }
    Ok(Equations {
        coordinates: form
            .coordinates
            .iter()
            .enumerate()
            .map(|(i, c)| (table.names.names[i][0].clone(), c.unit().to_string()))
            .collect(),
        poses: Vec::new(),
        kinetic: kinetic.as_ref().map(|t| table.formula(t)),
        potential: potential_printed.as_ref().map(|v| table.formula(v)),
        lagrangian: table.formula(&lagrangian),
        equations,
        constraints: constraint_equations,
        conserved_momenta,
        conserved_energy,
        accelerations,
    })
}

/// Every body's pose, simplified and printed.
pub(crate) fn poses(form: &CoordinateForm, symbols: &[String]) -> Result<Vec<BodyPose>, Unsupported> {
    let table = Table::new(form, symbols, 0);
    form.bodies
        .iter()
        .map(|b| {
            let formula = |e: Option<&Located>| -> Result<Formula, Unsupported> {
                Ok(table.formula(&table.located(e)?.simplify()?))
            };
            Ok(BodyPose {
                body: b.name.clone(),
                x: formula(Some(&b.x))?,
                y: formula(Some(&b.y))?,
                angle: formula(b.angle.as_ref())?,
            })
        })
        .collect()
}

/// The factors of every term of `p` (atoms to a positive power), each to its least power.
fn common_factors(p: &Poly) -> algebra::Monomial {
    let mut terms = p.0.keys();
    let Some(first) = terms.next() else { return algebra::Monomial::new() };
    let mut common: algebra::Monomial = first.iter().filter(|(_, e)| **e > 0).map(|(a, e)| (a.clone(), *e)).collect();
    for m in terms {
        common =
            common.into_iter().filter_map(|(a, e)| m.get(&a).filter(|f| **f > 0).map(|f| (a, e.min(*f)))).collect();
    }
    common
}

/// `n / d` with the factors common to every term of both divided out (the wedge's
/// `−m² g sin α cos α/(M m + m² sin² α)` is `−m g sin α cos α/(M + m sin² α)`).
fn cancel(n: &Poly, d: &Poly) -> Result<(Poly, Poly), Unsupported> {
    let (of_n, of_d) = (common_factors(n), common_factors(d));
    let shared: algebra::Monomial =
        of_n.iter().filter_map(|(a, e)| of_d.get(a).map(|f| (a.clone(), -(*e).min(*f)))).collect();
    if shared.is_empty() || n.is_zero() {
        return Ok((n.clone(), d.clone()));
    }
    let inverse = Poly(std::collections::BTreeMap::from([(shared, Rational::int(1))]));
    Ok((n.mul(&inverse)?, d.mul(&inverse)?))
}

/// `det a` of a square matrix of polynomials, by expansion along the first row.
fn determinant(a: &[Vec<Poly>]) -> Result<Poly, Unsupported> {
    if a.len() == 1 {
        return Ok(a[0][0].clone());
    }
    let mut det = Poly::zero();
    for j in 0..a.len() {
        det = det.add(&a[0][j].mul(&cofactor(a, 0, j)?)?)?;
    }
    Ok(det)
}

/// The cofactor `(−1)^(i+j) det` of `a` without row `i` and column `j`.
fn cofactor(a: &[Vec<Poly>], i: usize, j: usize) -> Result<Poly, Unsupported> {
    if a.len() == 1 {
        return Ok(Poly::constant(Rational::int(1)));
    }
    let minor: Vec<Vec<Poly>> = a
        .iter()
        .enumerate()
        .filter(|(r, _)| *r != i)
        .map(|(_, row)| row.iter().enumerate().filter(|(c, _)| *c != j).map(|(_, p)| p.clone()).collect())
        .collect();
    let det = determinant(&minor)?;
    Ok(if (i + j).is_multiple_of(2) { det } else { det.neg() })
}
