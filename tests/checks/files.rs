//! Scene files: every example file gives its built-in scene's equations to round-off, and every
//! malformed file in tests/files/bad gives one error at the right line and column.

use lagrange_scenes::Scene;
use lagrange_tests::scene;
use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("the tests crate is in the workspace").to_path_buf()
}

fn toml_files(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// The built-in scene a shipped file writes again: `<id>.toml` (coordinates form) or
/// `<id>.graph.toml` (joint-graph form).
fn twin(path: &Path) -> &'static dyn Scene {
    let stem = path.file_stem().and_then(|s| s.to_str()).expect("a file name");
    scene(stem.trim_end_matches(".graph"))
}

/// Largest entry of `a − b` relative to `1 + max |b|`.
fn relative_gap(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = 1.0 + b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0_f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// Round-off of q̈ between two evaluations of the same equations written differently (the
/// sums in another order, `r` for `√(x² + y²)`): measured at most 3.6e-15 relative over the
/// shipped files' samples; 1e-12 leaves a factor of about 300 for conditioning at other states.
const ROUND_OFF: f64 = 1e-12;

/// The multipliers of two systems with the same constraints agree: `Gᵀλ` (the generalized
/// constraint force, unique) to round-off, and `λ` itself where the rows are independent (at a
/// redundancy the engine's minimum-norm `λ` comes from a regularized solve, to its precision,
/// not to round-off). Whether the rows were independent.
fn same_multipliers(
    what: &str,
    a: &mut dyn lagrange::System,
    b: &mut dyn lagrange::System,
    t: f64,
    q: &[f64],
    qdot: &[f64],
) -> bool {
    let la = a.constraint_multipliers(t, q, qdot).unwrap().map(<[f64]>::to_vec);
    let lb = b.constraint_multipliers(t, q, qdot).unwrap().map(<[f64]>::to_vec);
    match (la, lb) {
        (Some(la), Some(lb)) => {
            let ga = a.constraint_jacobian(t, q, qdot).unwrap().expect("constrained").to_vec();
            let gb = b.constraint_jacobian(t, q, qdot).unwrap().expect("constrained").to_vec();
            let (c, n) = (lb.len(), q.len());
            let force = |g: &[f64], l: &[f64]| -> Vec<f64> {
                (0..n).map(|i| (0..c).map(|k| g[k * n + i] * l[k]).sum()).collect()
            };
            let (fa, fb) = (force(&ga, &la), force(&gb, &lb));
            assert!(relative_gap(&fa, &fb) <= ROUND_OFF, "{what}: Gᵀλ {fa:?} vs {fb:?}");
            let ggt: Vec<f64> =
                (0..c * c).map(|e| (0..n).map(|i| gb[(e / c) * n + i] * gb[(e % c) * n + i]).sum()).collect();
            // cond(G Gᵀ) at the shipped scenes' states: 1 … 1.2e2 with independent rows,
            // 1.3e16 (1/ε) at the redundant parallelogram; 1e8 splits them with a wide margin.
            let independent = lagrange_tests::condition_number(c, &ggt) < 1e8;
            if independent {
                assert!(relative_gap(&la, &lb) <= ROUND_OFF, "{what}: λ {la:?} vs {lb:?}");
            }
            independent
        }
        (None, None) => false,
        (la, lb) => panic!("{what}: multipliers {la:?} vs {lb:?}"),
    }
}

#[test]
fn every_example_file_gives_its_built_in_scene() {
    let files = toml_files(&workspace().join("examples/scenes"));
    assert!(files.len() >= 6, "{files:?}");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(24);
    let mut worst = 0.0_f64;
    for path in files {
        let file = lagrange_file::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        let built_in = twin(&path);
        let (fp, bp) = (file.default_params(), built_in.default_params());
        if let Some(mut graph) = file.joint_graph(&fp).unwrap() {
            // The joint-graph form: the built-in scene's graph to the bit, under another name.
            let theirs = built_in.joint_graph(&bp).unwrap().expect("the twin is a joint graph");
            graph.name.clone_from(&theirs.name);
            assert_eq!(graph, theirs, "{}", path.display());
        } else if let Some(shipped) = std::fs::read_to_string(&path)
            .ok()
            .filter(|text| text.starts_with(&format!("# `{}` in the coordinates form", built_in.id())))
        {
            // A joint graph's coordinates form, as `scenes --export ID --form coordinates`
            // writes it today (its parameters are the graph's: `g`, `m_<body>`, `I_<body>`).
            let written = lagrange_file::coordinates_file(built_in, &bp, file.id()).unwrap().expect("a joint graph");
            assert_eq!(shipped, written, "{}: regenerate it with `lagrange scenes --export`", path.display());
        } else {
            // The coordinates form: the built-in scene's parameters, by name or symbol.
            for (spec, value) in fp.iter() {
                let theirs =
                    bp.iter().find(|(s, _)| s.symbol == spec.name || s.name == spec.name || s.symbol == spec.symbol);
                let (_, expected) = theirs.unwrap_or_else(|| {
                    panic!("{}: parameter {} is not {}'s", path.display(), spec.name, built_in.id())
                });
                assert_eq!(value, expected, "{}: default of {}", path.display(), spec.name);
            }
        }
        let (s_file, s_built) = (file.default_state(&fp).unwrap(), built_in.default_state(&bp).unwrap());
        assert!(relative_gap(&s_file.q, &s_built.q) <= ROUND_OFF, "{}: {s_file:?} vs {s_built:?}", path.display());
        assert!(relative_gap(&s_file.qdot, &s_built.qdot) <= ROUND_OFF, "{}", path.display());
        let (mut a, mut b) = (file.build(&fp).unwrap(), built_in.build(&bp).unwrap());
        let constrained = a.constraint_counts() != (0, 0);
        for sample in 0..20 {
            // Unconstrained: anywhere near the default state; constrained: the default state
            // (consistent by construction) with the time moved.
            let (t, q, qdot) = if constrained || sample == 0 {
                (0.0, s_built.q.clone(), s_built.qdot.clone())
            } else {
                let q: Vec<f64> = s_built.q.iter().map(|v| v + rng.random_range(-0.2..0.2)).collect();
                (rng.random_range(0.0..2.0), q, s_built.qdot.iter().map(|_| rng.random_range(-1.0..1.0)).collect())
            };
            let qa = a.accelerations(t, &q, &qdot).unwrap().to_vec();
            let qb = b.accelerations(t, &q, &qdot).unwrap().to_vec();
            let gap = relative_gap(&qa, &qb);
            worst = worst.max(gap);
            assert!(gap <= ROUND_OFF, "{}: q̈ {qa:?} vs {qb:?} ({gap:e}) at {q:?}, {qdot:?}", path.display());
            let (ea, eb) = (a.energy_function(t, &q, &qdot).unwrap(), b.energy_function(t, &q, &qdot).unwrap());
            assert!((ea - eb).abs() <= ROUND_OFF * (1.0 + eb.abs()), "{}: energy {ea} vs {eb}", path.display());
            same_multipliers(&path.display().to_string(), a.as_mut(), b.as_mut(), t, &q, &qdot);
        }
    }
    eprintln!("largest relative gap in q̈ between a file and its built-in scene: {worst:.2e}");
}

/// The expectation a malformed file states on its first line: `# expect LINE:COLUMN MESSAGE`.
fn expectation(path: &Path) -> (usize, usize, String) {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
    match name {
        "empty.toml" => return (1, 1, "missing field `version`".into()),
        "binary.toml" => return (1, 1, "not a text file".into()),
        _ => {}
    }
    let text = std::fs::read_to_string(path).unwrap();
    let header = text
        .lines()
        .next()
        .and_then(|l| l.strip_prefix("# expect "))
        .unwrap_or_else(|| panic!("{name}: no expectation"));
    let (at, message) = header.split_once(' ').unwrap_or((header, ""));
    let (line, column) = at.split_once(':').expect("LINE:COLUMN");
    (line.parse().unwrap(), column.parse().unwrap(), message.to_string())
}

#[test]
fn every_malformed_file_gives_one_error_at_its_place() {
    let files = toml_files(&workspace().join("tests/files/bad"));
    assert!(files.len() >= 30, "{}", files.len());
    let mut wrong = Vec::new();
    for path in files {
        let (line, column, message) = expectation(&path);
        let error = match lagrange_file::load(&path) {
            Ok(scene) => {
                wrong.push(format!("{}: read as scene {}", path.display(), scene.id()));
                continue;
            }
            Err(lagrange_file::FileError::Invalid(d)) => d,
            Err(other) => panic!("{}: {other}", path.display()),
        };
        let rendered = error.render();
        // Drawn as rustc draws: the path with line and column, the line, a caret.
        let drawn = rendered.contains(&format!("{}:{line}:{column}", path.display())) && rendered.contains('^');
        if error.line_column() != (line, column) || !error.message().contains(&message) || !drawn {
            wrong.push(format!("{}: expected {line}:{column} `{message}`, got\n{rendered}", path.display()));
        }
    }
    assert!(wrong.is_empty(), "{} of the malformed files:\n{}", wrong.len(), wrong.join("\n"));
}

#[test]
fn suggestions_name_the_closest_known_name() {
    let path = workspace().join("tests/files/bad/unknown_name.toml");
    let Err(lagrange_file::FileError::Invalid(d)) = lagrange_file::load(&path) else { panic!("accepted") };
    assert_eq!(d.hint(), Some("did you mean `theta`?"));
}

/// The printed equations of every coordinates-form example, read back by the project's own
/// parser (their `plain` form) and evaluated at states where the engine gives `q̈`, `λ`, the
/// momenta and the energy: each equation holds to round-off.
#[test]
fn printed_equations_agree_with_the_engine() {
    use lagrange_file::tape::{Leaf, TapeBuilder};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(27);
    let (mut checked, mut graphs_checked) = (0, 0);
    let mut files = toml_files(&workspace().join("examples/scenes"));
    files.push(workspace().join("tests/files/watt_six_bar.toml"));
    for path in files {
        let equations = lagrange_file::eom(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        let scene = lagrange_file::load(&path).unwrap();
        let mut system = scene.build(&scene.default_params()).unwrap();
        // The names in the formulas: the file's own, or for a joint graph its coordinates
        // form's (whose poses and forces are composed from the graph; the engine evaluated
        // against is the graph's).
        let form = match lagrange_file::coordinates_file(scene.as_ref(), &scene.default_params(), "printed").unwrap() {
            Some(text) => lagrange_file::parse("printed.toml", &text).unwrap_or_else(|e| panic!("{}", e.render())),
            None => lagrange_file::load(&path).unwrap(),
        };
        let graph = scene.joint_graph(&scene.default_params()).unwrap().is_some();
        assert_eq!(!equations.poses.is_empty(), graph, "{}: poses for a joint graph only", path.display());
        let params = form.default_params();
        let names: Vec<String> = form.build(&params).unwrap().coordinates().iter().map(|c| c.name.clone()).collect();
        let n = names.len();
        let initial = scene.default_state(&scene.default_params()).unwrap();
        let constrained = system.constraint_counts() != (0, 0);
        for sample in 0..10 {
            let (t, q, qdot) = if constrained || sample == 0 {
                (initial.t, initial.q.clone(), initial.qdot.clone())
            } else {
                let q: Vec<f64> = initial.q.iter().map(|v| v + rng.random_range(-0.3..0.3)).collect();
                (rng.random_range(0.0..1.0), q, (0..n).map(|_| rng.random_range(-1.0..1.0)).collect())
            };
            let qddot = system.accelerations(t, &q, &qdot).unwrap().to_vec();
            let lambda = system.constraint_multipliers(t, &q, &qdot).unwrap().map(<[f64]>::to_vec).unwrap_or_default();
            let momenta = system.momenta(t, &q, &qdot).unwrap().to_vec();
            let energy = system.energy_function(t, &q, &qdot).unwrap();
            let mut inputs = vec![t];
            inputs.extend(&q);
            inputs.extend(&qdot);
            inputs.extend(&qddot);
            inputs.extend(&lambda);
            let value = |text: &str| -> f64 {
                let ast =
                    lagrange_file::expr::parse(text).unwrap_or_else(|e| panic!("{}: `{text}`: {e:?}", path.display()));
                let mut builder = TapeBuilder::new();
                let node = builder
                    .compile(&ast, &mut |name: &str, _: &std::ops::Range<usize>| -> Result<Leaf, String> {
                        if let Some((spec, v)) = params.iter().find(|(s, _)| s.name == name) {
                            let _ = spec;
                            return Ok(Leaf::Constant(v));
                        }
                        let index = |base: &str| names.iter().position(|c| c == base);
                        Ok(match name {
                            "t" => Leaf::Input(0),
                            "pi" => Leaf::Constant(std::f64::consts::PI),
                            _ => {
                                if let Some(i) = index(name) {
                                    Leaf::Input(1 + i)
                                } else if let Some(i) = name.strip_suffix("_ddot").and_then(index) {
                                    Leaf::Input(1 + 2 * n + i)
                                } else if let Some(i) = name.strip_suffix("_dot").and_then(index) {
                                    Leaf::Input(1 + n + i)
                                } else if let Some(k) =
                                    name.strip_prefix("lambda").and_then(|k| k.parse::<usize>().ok())
                                {
                                    Leaf::Input(3 * n + k)
                                } else {
                                    return Err(format!("unknown name `{name}`"));
                                }
                            }
                        })
                    })
                    .unwrap_or_else(|e| panic!("{}: `{text}`: {e}", path.display()));
                builder.output(node);
                let tape = builder.finish();
                let mut out = [0.0];
                tape.eval(&inputs, &mut vec![0.0; tape.len()], &mut out);
                out[0]
            };
            // Round-off of sums of a few terms of size up to |left| + |right| (and of the
            // engine's q̈, relative κ ε): 1e-10 of their size leaves a wide margin.
            let holds = |left: f64, right: f64, what: &str| {
                assert!(
                    (left - right).abs() <= 1e-10 * (1.0 + left.abs() + right.abs()),
                    "{}: {what}: {left} vs {right}",
                    path.display()
                );
            };
            for e in &equations.equations {
                holds(
                    value(&e.left.plain),
                    value(&e.right.plain),
                    &format!("{} = {}", e.left.unicode, e.right.unicode),
                );
                checked += 1;
                graphs_checked += usize::from(graph);
            }
            for e in &equations.constraints {
                holds(value(&e.left.plain), 0.0, &e.label);
            }
            for e in &equations.accelerations {
                holds(value(&e.left.plain), value(&e.right.plain), &e.left.unicode);
            }
            if let Some(h) = &equations.conserved_energy {
                holds(value(&h.right.plain), energy, "E");
            }
            for p in &equations.conserved_momenta {
                let i = names.iter().position(|c| p.left.plain == format!("p_{c}")).expect("a coordinate's momentum");
                holds(value(&p.right.plain), momenta[i], &p.left.unicode);
            }
        }
    }
    eprintln!("{checked} printed equations checked, {graphs_checked} of joint graphs");
    assert!(checked >= 50 && graphs_checked >= 200, "{checked}, {graphs_checked}");
}

/// A joint graph with every kind of joint and force element the shipped graphs lack: an absolute
/// clockwise angle, a slide, a fixed joint, a coupled joint, a joint that runs backwards, a
/// driven body, a point spring, a joint spring, both dampers, a torque and a force.
fn every_element_graph() -> lagrange_scenes::GraphScene {
    use lagrange::graph::{ForceElement, GraphBody, GraphJoint, JointGraph, Point, Profile};
    let graph = JointGraph::new("every_element", 9.81)
        .with_body(GraphBody::rigid("arm", 1.0, 0.1))
        .with_body(GraphBody::rigid("slider", 0.5, 0.01))
        .with_body(GraphBody::rigid("tab", 0.2, 0.005))
        .with_body(GraphBody::rigid("wheel", 0.3, 0.02))
        .with_body(GraphBody::rigid("tip", 0.1, 0.001))
        .with_body(GraphBody::rigid("driven", 0.4, 0.03))
        .with_joint(GraphJoint::revolute("a", "ground", [0.0, 0.0], "arm", [-0.5, 0.0]).absolute().clockwise())
        .with_joint(GraphJoint::prismatic("s", "arm", [0.0, 0.0], "slider", [0.0, 0.05], [0.6, 0.8]))
        .with_joint(GraphJoint::fixed("f", "slider", [0.1, 0.0], "tab", [0.0, -0.02], 0.3))
        .with_joint(GraphJoint::revolute("w", "arm", [0.5, 0.0], "wheel", [0.0, 0.0]))
        .with_joint(GraphJoint::revolute("r", "tip", [0.05, 0.0], "arm", [0.4, 0.1]))
        .with_joint(GraphJoint::revolute("d", "ground", [2.0, 0.0], "driven", [0.0, 0.3]).driven(Profile {
            constant: 0.2,
            rate: 0.1,
            amplitude: 0.3,
            frequency: 2.0,
            phase: 0.4,
        }))
        .with_coupling("w", "a", 2.0, 0.1)
        .with_force(ForceElement::Spring {
            a: Point::on("tab", [0.02, 0.0]),
            b: Point::on("driven", [0.0, -0.3]),
            stiffness: 20.0,
            rest_length: 0.5,
        })
        .with_force(ForceElement::JointSpring { joint: "a".into(), stiffness: 3.0, rest: 0.2 })
        .with_force(ForceElement::Damper {
            a: Point::world([0.0, -1.0]),
            b: Point::on("tip", [0.01, 0.02]),
            coefficient: 0.7,
        })
        .with_force(ForceElement::JointDamper { joint: "s".into(), coefficient: 0.4 })
        .with_force(ForceElement::Torque { body: "wheel".into(), torque: Profile::harmonic(0.5, 3.0) })
        .with_force(ForceElement::Force {
            at: Point::on("slider", [0.03, -0.01]),
            force: [Profile::ramp(1.0, 0.5), Profile::constant(-2.0)],
        });
    lagrange_scenes::GraphScene::new(graph, lagrange::State::new(0.0, vec![0.4, 0.3, -0.5], vec![0.7, -0.2, 1.1]))
        .expect("a valid graph")
}

/// Every joint graph written in the coordinates form (`lagrange scenes --export ID --form
/// coordinates`) gives the graph's `q̈`, multipliers and energy function: the file's poses,
/// constraints and forces are expressions composed from the graph, evaluated by the file's tapes,
/// against the graph's own forward kinematics and force elements.
#[test]
fn the_coordinates_form_of_every_graph_gives_the_graph() {
    let mut scenes: Vec<Box<dyn Scene>> = vec![Box::new(every_element_graph())];
    let mut files = toml_files(&workspace().join("examples/scenes"));
    files.push(workspace().join("tests/files/watt_six_bar.toml"));
    for path in files {
        let scene = lagrange_file::load(&path).unwrap_or_else(|e| panic!("{}", e.render()));
        if scene.joint_graph(&scene.default_params()).unwrap().is_some() {
            scenes.push(scene);
        }
    }
    assert!(scenes.len() >= 15, "{}", scenes.len());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(28);
    let (mut worst, mut independent) = (0.0_f64, 0);
    for graph in &scenes {
        let params = graph.default_params();
        let id = format!("{}_unfolded", graph.id());
        let text = lagrange_file::coordinates_file(graph.as_ref(), &params, &id).unwrap().expect("a joint graph");
        let file =
            lagrange_file::parse(&format!("{id}.toml"), &text).unwrap_or_else(|e| panic!("{}\n{text}", e.render()));
        let fp = file.default_params();
        let initial = graph.default_state(&params).unwrap();
        let state = file.default_state(&fp).unwrap();
        // The file's initial state is the graph's, projected again onto the constraints.
        assert!(relative_gap(&state.q, &initial.q) <= ROUND_OFF, "{id}: {state:?} vs {initial:?}");
        assert!(relative_gap(&state.qdot, &initial.qdot) <= ROUND_OFF, "{id}: {state:?} vs {initial:?}");
        let (mut a, mut b) = (file.build(&fp).unwrap(), graph.build(&params).unwrap());
        let constrained = b.constraint_counts() != (0, 0);
        for sample in 0..10 {
            // Unconstrained: anywhere near the initial state; constrained: the initial state at
            // other times with other rates.
            let t = if sample == 0 { 0.0 } else { rng.random_range(0.0..2.0) };
            let q: Vec<f64> = if constrained || sample == 0 {
                initial.q.clone()
            } else {
                initial.q.iter().map(|v| v + rng.random_range(-0.3..0.3)).collect()
            };
            let qdot: Vec<f64> = if sample == 0 {
                initial.qdot.clone()
            } else {
                initial.qdot.iter().map(|_| rng.random_range(-1.0..1.0)).collect()
            };
            // Constrained: rates projected onto the velocity constraints (off them, redundant
            // rows ask for contradicting accelerations and q̈ is a least-squares compromise).
            let (q, qdot) = if constrained {
                let held = vec![false; q.len()];
                let s = b.assemble(&lagrange::State::new(t, q, qdot), &held).unwrap();
                (s.q, s.qdot)
            } else {
                (q, qdot)
            };
            let qa = a.accelerations(t, &q, &qdot).unwrap().to_vec();
            let qb = b.accelerations(t, &q, &qdot).unwrap().to_vec();
            let gap = relative_gap(&qa, &qb);
            worst = worst.max(gap);
            assert!(gap <= ROUND_OFF, "{id}: q̈ {qa:?} vs {qb:?} ({gap:e}) at t = {t}, {q:?}, {qdot:?}");
            let (ea, eb) = (a.energy_function(t, &q, &qdot).unwrap(), b.energy_function(t, &q, &qdot).unwrap());
            assert!((ea - eb).abs() <= ROUND_OFF * (1.0 + eb.abs()), "{id}: energy {ea} vs {eb}");
            independent += usize::from(same_multipliers(&id, a.as_mut(), b.as_mut(), t, &q, &qdot));
        }
    }
    assert!(independent >= 50, "{independent} samples with independent constraints");
    eprintln!("largest relative gap in q̈ between a graph and its coordinates form: {worst:.2e}");
}
