//! The coordinates form: the lecture's steps i–iii in a file — parameters, coordinates, where
//! each body is — read, checked name by name, and compiled for the engine.

use crate::diagnostic::Diagnostic;
use crate::expr::{self, Ast, Span};
use crate::mechanism::{Bound, FileLagrangian, FileMechanism, Functions};
use crate::schema::{self, Expr, Kind, SceneFile};
use crate::tape::{Leaf, Node, TapeBuilder};
use lagrange::{Body, Coordinate, Description, Error, State};
use std::collections::HashMap;
use std::ops::Range;
use toml::Spanned;

/// An expression read from the file, with where its text lies in the file.
#[derive(Clone, Debug)]
pub(crate) struct Located {
    /// Its syntax tree.
    pub ast: Ast,
    /// The text as written.
    pub text: String,
    /// Where the expression's text starts in the file, when the file holds it verbatim.
    base: Option<usize>,
    /// The whole TOML value.
    whole: Range<usize>,
}

impl Located {
    /// The bytes of the file a span of the expression covers (the whole value where the
    /// string held escapes).
    pub fn file_span(&self, span: &Span) -> Range<usize> {
        match self.base {
            Some(base) => base + span.start..base + span.end,
            None => self.whole.clone(),
        }
    }
}

/// What a name may stand for in an expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Context {
    /// Masses, inertias, gravity, initial values: numbers and parameters.
    Constant,
    /// Positions, the potential, holonomic constraints: also `t` and the coordinates.
    Position,
    /// Forces, velocity constraints, a raw Lagrangian, the region: also the rates.
    Motion,
}

impl Context {
    fn what(self) -> &'static str {
        match self {
            Context::Constant => "a constant (mass, inertia, gravity, initial value)",
            Context::Position => "a position (x, y, angle, the potential, a constraint)",
            Context::Motion => "a force, velocity constraint, Lagrangian or bound",
        }
    }
}

/// A body as written.
#[derive(Clone, Debug)]
pub(crate) struct BodyExprs {
    pub name: String,
    pub mass: Located,
    pub inertia: Option<Located>,
    pub x: Located,
    pub y: Located,
    pub angle: Option<Located>,
}

/// A coordinates-form file, read and checked: every expression parsed and every name resolved.
#[derive(Clone, Debug)]
pub(crate) struct CoordinateForm {
    pub parameters: Vec<String>,
    pub coordinates: Vec<Coordinate>,
    pub initial: Vec<(Option<Located>, Option<Located>)>,
    pub gravity: Option<Located>,
    pub bodies: Vec<BodyExprs>,
    pub potential: Option<Located>,
    pub forces: Vec<(usize, Located)>,
    pub constraints: Vec<(String, Located)>,
    pub velocity_constraints: Vec<(String, Located)>,
    pub lagrangian: Option<Located>,
    pub region: Vec<(Located, bool, f64)>,
    /// Whether the poses are affine in the coordinates (a constant mass matrix).
    pub constant_mass_matrix: bool,
    /// Where each coordinate is declared (for errors the engine finds at the initial state).
    pub coordinate_spans: Vec<Range<usize>>,
    /// Where each constraint is declared.
    pub constraint_spans: Vec<Range<usize>>,
}

/// Reads one file's values, turning each problem into a [`Diagnostic`] at its place.
pub(crate) struct Reader<'a> {
    pub path: &'a str,
    pub source: &'a str,
}

impl Reader<'_> {
    /// An error about `span` of the file.
    pub fn error(&self, span: Range<usize>, message: impl Into<String>) -> Diagnostic {
        Diagnostic::new(self.path, self.source, span, message)
    }

    /// Parse an expression where it stands in the file.
    pub fn expression(&self, value: &Spanned<Expr>) -> Result<Located, Diagnostic> {
        let whole = value.span();
        match value.get_ref() {
            Expr::Number(v) => {
                if !v.is_finite() {
                    return Err(self.error(whole, format!("{v} is not a finite number")).label("not finite"));
                }
                let text = format!("{v}");
                Ok(Located { ast: Ast::Number(*v, 0..text.len()), text, base: None, whole })
            }
            Expr::Text(text) => {
                let raw = &self.source[whole.clone()];
                // The expression's own bytes, when the string is written without escapes.
                let base = ["\"\"\"", "'''", "\"", "'"].iter().find_map(|quote| {
                    let inner = raw.strip_prefix(quote)?.strip_suffix(quote)?;
                    let skip = quote.len() + if quote.len() == 3 && inner.starts_with('\n') { 1 } else { 0 };
                    (self.source.get(whole.start + skip..whole.start + skip + text.len()) == Some(text.as_str()))
                        .then_some(whole.start + skip)
                });
                let located = |ast| Located { ast, text: text.clone(), base, whole: whole.clone() };
                expr::parse(text).map(located).map_err(|e| {
                    let span = located(Ast::Number(0.0, 0..0)).file_span(&e.span);
                    self.error(span, e.message).label("here").with_hint(e.hint)
                })
            }
        }
    }
}

/// The names a file's expressions may use and what each stands for.
#[derive(Clone, Debug)]
pub(crate) struct Scope {
    /// Parameter names, in order (their values are given when compiling).
    pub parameters: Vec<String>,
    /// Coordinate names, in order.
    pub coordinates: Vec<String>,
}

/// The suffix that names a coordinate's rate (`theta_dot`).
pub const RATE_SUFFIX: &str = "_dot";

impl Scope {
    /// What `name` stands for in `context` with parameter `values`, or why it cannot be used.
    pub fn resolve(&self, name: &str, context: Context, values: &[f64]) -> Result<Leaf, (String, Option<String>)> {
        let n = self.coordinates.len();
        if let Some(i) = self.parameters.iter().position(|p| p == name) {
            return Ok(Leaf::Constant(values[i]));
        }
        if name == "pi" {
            return Ok(Leaf::Constant(std::f64::consts::PI));
        }
        let coordinate = self.coordinates.iter().position(|c| c == name);
        let rate = name.strip_suffix(RATE_SUFFIX).and_then(|c| self.coordinates.iter().position(|x| x == c));
        match (context, name, coordinate, rate) {
            (Context::Constant, "t", ..) | (Context::Constant, _, Some(_), _) | (Context::Constant, _, _, Some(_)) => {
                Err((
                    format!("`{name}` changes with the motion, but this is {}", context.what()),
                    Some("use numbers and parameters only".into()),
                ))
            }
            (_, "t", ..) => Ok(Leaf::Input(0)),
            (_, _, Some(i), _) => Ok(Leaf::Input(1 + i)),
            (Context::Position, _, _, Some(_)) => Err((
                format!("the rate `{name}` cannot appear in {}", context.what()),
                Some("positions, the potential and holonomic constraints depend on t and the coordinates only".into()),
            )),
            (_, _, _, Some(i)) => Ok(Leaf::Input(1 + n + i)),
            _ => {
                let mut known: Vec<&str> = self.parameters.iter().map(String::as_str).collect();
                known.push("pi");
                if context != Context::Constant {
                    known.push("t");
                    known.extend(self.coordinates.iter().map(String::as_str));
                }
                let rates: Vec<String> = self.coordinates.iter().map(|c| format!("{c}{RATE_SUFFIX}")).collect();
                if context == Context::Motion {
                    known.extend(rates.iter().map(String::as_str));
                }
                let hint = crate::names::suggest(name, known.iter().copied()).map(|s| format!("did you mean `{s}`?"));
                Err((
                    format!("unknown name `{name}`"),
                    hint.or_else(|| Some(format!("known here: {}", known.join(", ")))),
                ))
            }
        }
    }
}

/// Compile `located` into `builder` in `context`.
pub(crate) fn compile(
    builder: &mut TapeBuilder,
    scope: &Scope,
    located: &Located,
    context: Context,
    values: &[f64],
) -> Result<Node, (Range<usize>, String, Option<String>)> {
    builder.compile(&located.ast, &mut |name: &str, span: &Span| {
        scope.resolve(name, context, values).map_err(|(message, hint)| (located.file_span(span), message, hint))
    })
}

/// The value of a constant expression.
pub(crate) fn constant(
    scope: &Scope,
    located: &Located,
    values: &[f64],
) -> Result<f64, (Range<usize>, String, Option<String>)> {
    let mut builder = TapeBuilder::new();
    let node = compile(&mut builder, scope, located, Context::Constant, values)?;
    match builder.value(node) {
        Some(v) if v.is_finite() => Ok(v),
        _ => Err((
            located.file_span(&located.ast.span()),
            format!("`{}` is not a finite number with these parameters", located.text),
            None,
        )),
    }
}

impl CoordinateForm {
    /// Read the coordinates form of `file`, with the file's `parameters` (names in order).
    pub fn read(reader: &Reader<'_>, file: &SceneFile, parameters: Vec<String>) -> Result<Self, Diagnostic> {
        if file.coordinates.is_empty() {
            return Err(reader
                .error(file.id.span(), "the scene has no coordinates")
                .label("a mechanism needs at least one generalized coordinate")
                .with_hint(Some("add [[coordinates]] with name and kind (angle or length)".into())));
        }
        let mut names = Names::default();
        for p in &file.parameters {
            names.declare(reader, &p.name, "parameter")?;
        }
        let mut coordinates = Vec::new();
        let mut initial = Vec::new();
        let mut coordinate_spans = Vec::new();
        for c in &file.coordinates {
            names.declare(reader, &c.name, "coordinate")?;
            let rate = Spanned::new(c.name.span(), format!("{}{RATE_SUFFIX}", c.name.get_ref()));
            names.declare(reader, &rate, "rate of a coordinate")?;
            coordinates.push(match c.kind {
                Kind::Angle => Coordinate::angle(c.name.get_ref()),
                Kind::Length => Coordinate::length(c.name.get_ref()),
            });
            let optional = |v: &Option<Spanned<Expr>>| v.as_ref().map(|v| reader.expression(v)).transpose();
            initial.push((optional(&c.initial)?, optional(&c.rate)?));
            coordinate_spans.push(c.name.span());
        }
        let optional = |v: &Option<Spanned<Expr>>| v.as_ref().map(|v| reader.expression(v)).transpose();
        // Bodies and constraints are named apart from the expressions' names (no expression
        // uses them): a body may be called as its mass is.
        let mut body_names = Names::default();
        let mut bodies = Vec::new();
        for b in &file.bodies {
            body_names.declare(reader, &b.name, "body")?;
            bodies.push(BodyExprs {
                name: b.name.get_ref().clone(),
                mass: reader.expression(&b.mass)?,
                inertia: optional(&b.inertia)?,
                x: reader.expression(&b.x)?,
                y: reader.expression(&b.y)?,
                angle: optional(&b.angle)?,
            });
        }
        let mut forces = Vec::new();
        for f in &file.forces {
            let Some(i) = file.coordinates.iter().position(|c| c.name.get_ref() == f.coordinate.get_ref()) else {
                let known = file.coordinates.iter().map(|c| c.name.get_ref().as_str());
                return Err(reader
                    .error(
                        f.coordinate.span(),
                        format!("no coordinate `{}` to apply a force along", f.coordinate.get_ref()),
                    )
                    .label("not a coordinate")
                    .with_hint(
                        crate::names::suggest(f.coordinate.get_ref(), known).map(|s| format!("did you mean `{s}`?")),
                    ));
            };
            forces.push((i, reader.expression(&f.force)?));
        }
        let mut constraint_spans = Vec::new();
        let mut row_names = Names::default();
        let mut rows =
            |entries: &[schema::ConstraintEntry], what: &'static str| -> Result<Vec<(String, Located)>, Diagnostic> {
                let mut out = Vec::new();
                for e in entries {
                    row_names.declare(reader, &e.name, what)?;
                    constraint_spans.push(e.name.span());
                    out.push((e.name.get_ref().clone(), reader.expression(&e.residual)?));
                }
                Ok(out)
            };
        let constraints = rows(&file.constraints, "constraint")?;
        let velocity_constraints = rows(&file.velocity_constraints, "velocity constraint")?;
        let mut region = Vec::new();
        for bound in &file.region {
            let quantity = reader.expression(&bound.quantity)?;
            let (above, limit) = match (bound.above, bound.below) {
                (Some(limit), None) => (true, limit),
                (None, Some(limit)) => (false, limit),
                _ => {
                    return Err(reader
                        .error(bound.quantity.span(), "a bound of the region needs one of `above` and `below`")
                        .label("this quantity")
                        .with_hint(Some("e.g. quantity = \"r\", above = 0".into())));
                }
            };
            if !limit.is_finite() {
                return Err(reader.error(bound.quantity.span(), format!("the bound {limit} is not finite")));
            }
            region.push((quantity, above, limit));
        }
        let mut form = Self {
            constant_mass_matrix: false,
            parameters,
            coordinates,
            initial,
            gravity: optional(&file.gravity)?,
            bodies,
            potential: optional(&file.potential)?,
            forces,
            constraints,
            velocity_constraints,
            lagrangian: optional(&file.lagrangian)?,
            region,
            coordinate_spans,
            constraint_spans,
        };
        form.check_shape(reader, file)?;
        form.constant_mass_matrix = crate::symbolic::constant_mass_matrix(&form);
        Ok(form)
    }

    /// Bodies or a Lagrangian, not both and not neither; every coordinate moves a body.
    fn check_shape(&self, reader: &Reader<'_>, file: &SceneFile) -> Result<(), Diagnostic> {
        match (&self.lagrangian, self.bodies.is_empty()) {
            (Some(_), false) => {
                return Err(reader
                    .error(file.bodies[0].name.span(), "a file gives bodies or a Lagrangian, not both")
                    .label("a body")
                    .with_hint(Some(
                        "remove `lagrangian` to derive L from the bodies, or the bodies to use it".into(),
                    )));
            }
            (None, true) => {
                return Err(reader
                    .error(file.id.span(), "the scene has neither bodies nor a Lagrangian")
                    .label("nothing moves")
                    .with_hint(Some("add [[bodies]] with mass, x and y, or a `lagrangian`".into())));
            }
            (Some(l), true) if !self.constraints.is_empty() || !self.velocity_constraints.is_empty() => {
                return Err(reader
                    .error(l.whole.clone(), "a raw Lagrangian takes no constraints")
                    .label("this Lagrangian")
                    .with_hint(Some("write the system with bodies to constrain it".into())));
            }
            (Some(_), true) if self.potential.is_some() || self.gravity.is_some() => {
                return Err(reader
                    .error(l_span(self), "a raw Lagrangian holds its potential: `potential` and `gravity` do not apply")
                    .with_hint(Some("write L = T − V in `lagrangian`".into())));
            }
            _ => {}
        }
        if self.lagrangian.is_none() {
            let mut moved = vec![false; self.coordinates.len()];
            for body in &self.bodies {
                for e in [Some(&body.x), Some(&body.y), body.angle.as_ref()].into_iter().flatten() {
                    e.ast.names(&mut |name, _| {
                        if let Some(i) = self.coordinates.iter().position(|c| c.name == name) {
                            moved[i] = true;
                        }
                    });
                }
            }
            if let Some(i) = moved.iter().position(|m| !m) {
                return Err(reader
                    .error(
                        self.coordinate_spans[i].clone(),
                        format!(
                            "no body moves with the coordinate `{}`: the mass matrix would be singular",
                            self.coordinates[i].name
                        ),
                    )
                    .label("in no body's x, y or angle")
                    .with_hint(Some("use it in a body's position, or remove it".into())));
            }
        }
        Ok(())
    }

    /// Compile every function at the parameter `values` into the engine's system.
    ///
    /// # Errors
    /// The place and reason of the first expression that does not compile in its context.
    pub fn compile(&self, values: &[f64]) -> Result<Compiled, (Range<usize>, String, Option<String>)> {
        let scope = Scope {
            parameters: self.parameters.clone(),
            coordinates: self.coordinates.iter().map(|c| c.name.clone()).collect(),
        };
        let tape =
            |items: &[(&Located, Context)]| -> Result<crate::tape::Tape, (Range<usize>, String, Option<String>)> {
                let mut builder = TapeBuilder::new();
                for (located, context) in items {
                    let node = compile(&mut builder, &scope, located, *context, values)?;
                    builder.output(node);
                }
                Ok(builder.finish())
            };
        let zero = Located { ast: Ast::Number(0.0, 0..1), text: "0".into(), base: None, whole: 0..0 };
        let mut pose_items = Vec::new();
        let mut bodies = Vec::new();
        for b in &self.bodies {
            pose_items.extend([
                (&b.x, Context::Position),
                (&b.y, Context::Position),
                (b.angle.as_ref().unwrap_or(&zero), Context::Position),
            ]);
            let mass = constant(&scope, &b.mass, values)?;
            let inertia = b.inertia.as_ref().map(|i| constant(&scope, i, values)).transpose()?.unwrap_or(0.0);
            for (value, what, e) in
                [(mass, "mass", &b.mass), (inertia, "inertia", b.inertia.as_ref().unwrap_or(&b.mass))]
            {
                if value < 0.0 {
                    return Err((
                        e.file_span(&e.ast.span()),
                        format!("the {what} of `{}` is negative ({value})", b.name),
                        None,
                    ));
                }
            }
            bodies.push(if inertia == 0.0 { Body::point(&b.name, mass) } else { Body::rigid(&b.name, mass, inertia) });
        }
        let gravity = self.gravity.as_ref().map(|g| constant(&scope, g, values)).transpose()?.unwrap_or(0.0);
        let functions = Functions {
            poses: tape(&pose_items)?,
            potential: self.potential.as_ref().map(|v| tape(&[(v, Context::Position)])).transpose()?,
            // Forces that the parameters make 0 (a damping coefficient c = 0) are no forces: the
            // engine then skips the stage, as for a built-in scene.
            forces: (!self.forces.is_empty())
                .then(|| tape(&self.forces.iter().map(|(_, f)| (f, Context::Motion)).collect::<Vec<_>>()))
                .transpose()?
                .filter(|t| !t.is_zero()),
            forced: self.forces.iter().map(|(i, _)| *i).collect(),
            constraints: tape(&self.constraints.iter().map(|(_, c)| (c, Context::Position)).collect::<Vec<_>>())?,
            velocity: tape(&self.velocity_constraints.iter().map(|(_, c)| (c, Context::Motion)).collect::<Vec<_>>())?,
            lagrangian: self.lagrangian.as_ref().map(|l| tape(&[(l, Context::Motion)])).transpose()?,
            region: tape(&self.region.iter().map(|(q, ..)| (q, Context::Motion)).collect::<Vec<_>>())?,
            bounds: self
                .region
                .iter()
                .map(|(q, above, limit)| Bound {
                    quantity: format!("{} {} {limit}", q.text, if *above { ">" } else { "<" }),
                    above: *above,
                    limit: *limit,
                })
                .collect(),
        };
        let mut initial_q = Vec::new();
        let mut initial_rate = Vec::new();
        for (q, rate) in &self.initial {
            initial_q.push(q.as_ref().map(|v| constant(&scope, v, values)).transpose()?.unwrap_or(0.0));
            initial_rate.push(rate.as_ref().map(|v| constant(&scope, v, values)).transpose()?.unwrap_or(0.0));
        }
        let initial = State::new(0.0, initial_q, initial_rate);
        if self.lagrangian.is_some() {
            return Ok(Compiled::Raw(FileLagrangian::new(self.coordinates.clone(), functions), initial));
        }
        let mut description = Description::new().gravity(gravity);
        description.coordinates = self.coordinates.clone();
        description.bodies = bodies;
        description.constraints = self.constraints.iter().map(|(n, _)| n.clone()).collect();
        description.velocity_constraints = self.velocity_constraints.iter().map(|(n, _)| n.clone()).collect();
        // Poses affine in q (Atwood machines, the wedge): M is factored once (the engine checks
        // the declaration at its probe states).
        description.constant_mass_matrix = self.constant_mass_matrix;
        Ok(Compiled::Bodies(FileMechanism::new(description, functions), initial))
    }
}

fn l_span(form: &CoordinateForm) -> Range<usize> {
    form.lagrangian.as_ref().map_or(0..0, |l| l.whole.clone())
}

/// A coordinates-form file compiled for one set of parameters: the engine's input and the
/// initial state the file gives.
#[derive(Clone, Debug)]
pub(crate) enum Compiled {
    /// Bodies placed by expressions.
    Bodies(FileMechanism, State),
    /// A raw Lagrangian.
    Raw(FileLagrangian, State),
}

impl Compiled {
    /// The engine's model behind the dynamic facade.
    pub fn system(self) -> Result<(Box<dyn lagrange::System>, State), Error> {
        Ok(match self {
            Compiled::Bodies(m, s) => (Box::new(lagrange::Buffered::new(lagrange::Model::new(m)?)), s),
            Compiled::Raw(l, s) => (Box::new(lagrange::Buffered::new(lagrange::RawModel::new(l)?)), s),
        })
    }
}

/// Names declared so far, each with where (a name is declared once in a file).
#[derive(Default)]
struct Names {
    seen: HashMap<String, (Range<usize>, &'static str)>,
}

impl Names {
    fn declare(&mut self, reader: &Reader<'_>, name: &Spanned<String>, what: &'static str) -> Result<(), Diagnostic> {
        let text = name.get_ref();
        let expression_name = matches!(what, "parameter" | "coordinate" | "rate of a coordinate");
        let valid = expr::parse(text).is_ok_and(|ast| matches!(ast, Ast::Name(ref n, _) if n == text));
        if text.is_empty()
            || (expression_name && !valid)
            || text == "t"
            || text == "pi"
            || expr::Function::named(text).is_some()
        {
            return Err(reader
                .error(name.span(), format!("`{text}` cannot name a {what}"))
                .label("not a free name")
                .with_hint(Some(
                    "names are letters, digits, `_` and `'`, starting with a letter; t, pi and the functions are taken"
                        .into(),
                )));
        }
        if let Some((earlier, kind)) = self.seen.get(text) {
            let (line, _) = Diagnostic::new(reader.path, reader.source, earlier.clone(), "").line_column();
            return Err(reader
                .error(name.span(), format!("`{text}` is declared twice"))
                .label(format!("already a {kind} on line {line}"))
                .with_hint(Some(
                    "parameters, coordinates and their rates have names of their own, as do bodies and constraints"
                        .into(),
                )));
        }
        self.seen.insert(text.clone(), (name.span(), what));
        Ok(())
    }
}
