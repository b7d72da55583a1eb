//! What a drawing of a scene shows, apart from where its bodies are: each body's figure in its
//! own frame, the joints' pins and slides, rods, ropes, springs and dampers between points, and
//! the fixed points of the world. Poses over time come from the runs; a front end (the
//! animation, docs/animation.md) draws this sketch at each frame's poses.
//!
//! A joint graph's sketch follows from the graph ([`Sketch::from_graph`]): a body with a shape
//! is drawn as that shape, a point mass as a dot with rods to its joints' anchors (a bob on a
//! rod), any other body as the link joining its joints' anchors and its centre of mass; revolute joints are pins, prismatic
//! joints slides — or ropes where a coupling ties them to a revolute joint (a rope over a
//! pulley, whose radius the coupling's ratio gives). The hand-written scenes sketch themselves
//! (a spring from the pivot, a rod to the driven support, the incline under the disc); a scene
//! with neither ([`Sketch::of_bodies`]) shows its bodies alone.

use crate::scenes::{MaximalScene, MaximalVisitor};
use lagrange::graph::{ForceElement, GROUND, JointGraph, JointType, Point, Shape};
use lagrange::{Body, Error};
use lagrange_scenes::{Params, Scene};
use serde::Serialize;

/// A drawing of a mechanism, without its poses. Bodies are in the reduced model's order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sketch {
    /// One figure per body, in the body's frame (centre of mass at the origin).
    pub bodies: Vec<Figure>,
    /// Straight connections between two points: rods, ropes, springs, dampers.
    pub links: Vec<Link>,
    /// Revolute joints: a pin at a point.
    pub pins: Vec<Anchor>,
    /// Slides: a line through a point along a direction of that point's frame (a prismatic
    /// joint's guide, an incline, a rail).
    pub slides: Vec<Slide>,
    /// Fixed points of the world that carry something (a pivot, a centre of attraction).
    pub fixed: Vec<[f64; 2]>,
}

/// How a body is drawn, in its own frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Figure {
    /// A point mass: a dot at the centre of mass.
    Dot,
    /// A disc of `radius` (m), with a mark along its `x` axis so that its turning shows.
    Disc {
        /// Radius (m).
        radius: f64,
    },
    /// A rectangle of half-extents `(a, b)` (m) along the body's axes.
    Rectangle {
        /// Half-extents (m).
        half_extents: [f64; 2],
    },
    /// A link: the convex outline of these points (two: a bar between them), e.g. the anchors
    /// of its joints and its centre of mass.
    Link {
        /// Points in the body's frame (m).
        points: Vec<[f64; 2]>,
    },
}

/// A point of the drawing: fixed in the world, fixed in a body, or moving with time.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Anchor {
    /// A fixed point of the world (m).
    World {
        /// Position (m).
        at: [f64; 2],
    },
    /// The point `at` of body `body`'s frame.
    Body {
        /// Index of the body.
        body: usize,
        /// Position in the body's frame (m).
        at: [f64; 2],
    },
    /// A point moving along `x` as `centre + (A sin ωt, 0)` (the driven pendulum's support).
    Harmonic {
        /// Centre of the motion (m).
        centre: [f64; 2],
        /// Amplitude `A` (m).
        amplitude: f64,
        /// Angular frequency `ω` (rad/s).
        frequency: f64,
    },
}

/// What a [`Link`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LinkKind {
    /// A massless rigid rod.
    Rod,
    /// A rope (in tension, straight).
    Rope,
    /// A spring, drawn as a zig-zag.
    Spring,
    /// A damper, drawn as a dashpot.
    Damper,
}

/// A straight connection between two points.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Link {
    /// Rod, rope, spring or damper.
    pub kind: LinkKind,
    /// One end.
    pub a: Anchor,
    /// The other end.
    pub b: Anchor,
}

/// A line through a point along a direction, both in the point's frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Slide {
    /// A point of the line.
    pub at: Anchor,
    /// Its direction, in the frame of `at` (the world's for a world point).
    pub axis: [f64; 2],
}

/// How a body is drawn from its mass properties alone: a point mass as a dot, a body with
/// inertia as the uniform rod of that inertia along its `x` axis (length `√(12 I/m)`), or a disc
/// of radius 0.1 m for a body with inertia and no mass.
fn figure(body: &Body) -> Figure {
    match (body.mass > 0.0, body.inertia > 0.0) {
        (_, false) => Figure::Dot,
        (true, true) => {
            let half = 0.5 * (12.0 * body.inertia / body.mass).sqrt();
            Figure::Link { points: vec![[-half, 0.0], [half, 0.0]] }
        }
        (false, true) => Figure::Disc { radius: 0.1 },
    }
}

impl Sketch {
    /// `bodies` figures and nothing else.
    fn with(bodies: Vec<Figure>) -> Sketch {
        Sketch { bodies, links: Vec::new(), pins: Vec::new(), slides: Vec::new(), fixed: Vec::new() }
    }

    /// The bodies alone, each drawn from its mass properties: point masses as dots, bodies with
    /// inertia as the uniform rod of that inertia along their `x` axis (length `√(12 I/m)`), or
    /// a disc of radius 0.1 m for a body with inertia and no mass.
    pub fn of_bodies(bodies: &[Body]) -> Sketch {
        Sketch::with(bodies.iter().map(figure).collect())
    }

    /// One point mass (body 0), and a fixed point at the origin it is held by: by a spring,
    /// by a rod, or (none) by a central force.
    pub(crate) fn particle_from_origin(kind: Option<LinkKind>) -> Sketch {
        let origin = Anchor::World { at: [0.0, 0.0] };
        let links = kind
            .map(|kind| Link { kind, a: origin.clone(), b: Anchor::Body { body: 0, at: [0.0, 0.0] } })
            .into_iter()
            .collect();
        let pins = if kind == Some(LinkKind::Rod) { vec![origin] } else { Vec::new() };
        Sketch { links, pins, fixed: vec![[0.0, 0.0]], ..Sketch::with(vec![Figure::Dot]) }
    }

    /// The sketch of a joint graph (see the module's documentation).
    pub fn from_graph(graph: &JointGraph) -> Sketch {
        let index = |name: &str| graph.bodies.iter().position(|b| b.name == name);
        let anchor = |body: &str, at: [f64; 2]| match index(body) {
            Some(body) => Anchor::Body { body, at },
            None => Anchor::World { at },
        };
        let mut sketch = Sketch::with(Vec::new());
        let fixed = |sketch: &mut Sketch, at: [f64; 2]| {
            if !sketch.fixed.contains(&at) {
                sketch.fixed.push(at);
            }
        };
        // Points each body carries, in its frame.
        let mut carried: Vec<Vec<[f64; 2]>> = vec![Vec::new(); graph.bodies.len()];
        let mut carry = |body: &str, at: [f64; 2]| {
            if let Some(b) = index(body)
                && !carried[b].contains(&at)
            {
                carried[b].push(at);
            }
        };
        // A pulley's radius from a coupling between its revolute joint and a prismatic one.
        let mut radius: Vec<Option<f64>> = vec![None; graph.bodies.len()];
        let joint = |name: &str| graph.joints.iter().find(|j| j.name == name);
        let mut roped: Vec<&str> = Vec::new();
        for coupling in &graph.couplings {
            let (Some(coupled), Some(source)) = (joint(&coupling.joint), joint(&coupling.source)) else { continue };
            let pair = match (&coupled.kind, &source.kind) {
                // q_revolute = ratio · q_prismatic: the rope's length per radian is 1/ratio.
                (JointType::Revolute, JointType::Prismatic { .. }) => Some((coupled, 1.0 / coupling.ratio.abs())),
                (JointType::Prismatic { .. }, JointType::Revolute) => Some((source, coupling.ratio.abs())),
                _ => None,
            };
            if let Some(b) = pair.and_then(|(revolute, r)| index(&revolute.child).filter(|_| r.is_finite() && r > 0.0))
            {
                radius[b] = pair.map(|(_, r)| r);
            }
        }
        // Any prismatic joint a coupling ties to another joint is a rope (the other end of a
        // rope over a pulley, a rope over a movable pulley).
        for coupling in &graph.couplings {
            for name in [&coupling.joint, &coupling.source] {
                if joint(name).is_some_and(|j| matches!(j.kind, JointType::Prismatic { .. })) {
                    roped.push(name);
                }
            }
        }
        for j in &graph.joints {
            carry(&j.parent, j.parent_anchor);
            carry(&j.child, j.child_anchor);
            match j.kind {
                JointType::Revolute => {
                    sketch.pins.push(anchor(&j.parent, j.parent_anchor));
                    if j.parent == GROUND {
                        fixed(&mut sketch, j.parent_anchor);
                    }
                }
                JointType::Prismatic { .. } if roped.contains(&j.name.as_str()) => {
                    let (a, b) = (anchor(&j.parent, j.parent_anchor), anchor(&j.child, j.child_anchor));
                    sketch.links.push(Link { kind: LinkKind::Rope, a, b });
                    if j.parent == GROUND {
                        fixed(&mut sketch, j.parent_anchor);
                    }
                }
                JointType::Prismatic { axis } => {
                    sketch.slides.push(Slide { at: anchor(&j.parent, j.parent_anchor), axis });
                }
                JointType::Fixed { .. } => {}
            }
        }
        for force in &graph.forces {
            let mut between = |kind, a: &Point, b: &Point| {
                carry(&a.body, a.at);
                carry(&b.body, b.at);
                for p in [a, b] {
                    if p.body == GROUND {
                        fixed(&mut sketch, p.at);
                    }
                }
                sketch.links.push(Link { kind, a: anchor(&a.body, a.at), b: anchor(&b.body, b.at) });
            };
            match force {
                ForceElement::Spring { a, b, .. } => between(LinkKind::Spring, a, b),
                ForceElement::Damper { a, b, .. } => between(LinkKind::Damper, a, b),
                // A spring along a slide: from a wall behind the slide's origin to the body.
                ForceElement::JointSpring { joint: name, .. } => {
                    if let Some(j) = joint(name)
                        && let JointType::Prismatic { axis } = j.kind
                    {
                        let norm = axis[0].hypot(axis[1]).max(f64::MIN_POSITIVE);
                        let wall = [j.parent_anchor[0] - axis[0] / norm, j.parent_anchor[1] - axis[1] / norm];
                        let (a, b) = (anchor(&j.parent, wall), anchor(&j.child, j.child_anchor));
                        if j.parent == GROUND {
                            fixed(&mut sketch, wall);
                        }
                        sketch.links.push(Link { kind: LinkKind::Spring, a, b });
                    }
                }
                _ => {}
            }
        }
        for (b, body) in graph.bodies.iter().enumerate() {
            if body.shape.is_none() && radius[b].is_none() && body.inertia == 0.0 && body.mass > 0.0 {
                for &at in carried[b].iter().filter(|at| **at != [0.0, 0.0]) {
                    let (a, b) = (Anchor::Body { body: b, at }, Anchor::Body { body: b, at: [0.0, 0.0] });
                    sketch.links.push(Link { kind: LinkKind::Rod, a, b });
                }
            }
        }
        sketch.bodies = graph
            .bodies
            .iter()
            .zip(&carried)
            .zip(&radius)
            .map(|((body, points), radius)| match (body.shape, *radius) {
                (Some(Shape::Disc { radius }), _) | (None, Some(radius)) => Figure::Disc { radius },
                (Some(Shape::Rectangle { half_extents }), _) => Figure::Rectangle { half_extents },
                // A point mass on rods to its joints: a dot, the rods drawn as links below.
                (None, None) if body.inertia == 0.0 && body.mass > 0.0 => Figure::Dot,
                (None, None) => {
                    let mut points = points.clone();
                    if body.mass > 0.0 && !points.contains(&[0.0, 0.0]) {
                        points.push([0.0, 0.0]);
                    }
                    match points.len() {
                        0 | 1 => {
                            Sketch::of_bodies(&[Body::rigid(&body.name, body.mass, body.inertia)]).bodies.remove(0)
                        }
                        _ => Figure::Link { points },
                    }
                }
            })
            .collect();
        sketch
    }
}

/// The sketch of `scene` with `params`: from its joint graph, its hand-written maximal
/// description, or (neither) its bodies alone.
///
/// # Errors
/// Invalid parameters.
pub fn sketch(scene: &dyn Scene, params: &Params) -> Result<Sketch, Error> {
    if let Some(graph) = scene.joint_graph(params)? {
        return Ok(Sketch::from_graph(&graph));
    }
    struct Drawn;
    impl MaximalVisitor for Drawn {
        type Output = Sketch;
        fn visit<T: MaximalScene>(self, scene: T) -> Sketch {
            scene.sketch()
        }
    }
    if crate::scenes::has_description(scene, params)? {
        return crate::scenes::visit(scene, params, Drawn);
    }
    Ok(Sketch::of_bodies(scene.build(params)?.bodies()))
}
