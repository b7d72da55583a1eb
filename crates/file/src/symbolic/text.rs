//! The equations as text: Unicode as a textbook prints them, or LaTeX (an `align*`
//! environment) — what `lagrange eom` prints and the Python package's `Equations` shows.

use super::{Equation, Equations, Formula};

fn line(out: &mut String, text: &str) {
    out.push_str(text);
    out.push('\n');
}

fn side(f: &Formula) -> &str {
    &f.unicode
}

/// The equations in Unicode as a textbook prints them, a block per kind, headed `Equations of
/// {title}`.
pub fn unicode(title: &str, e: &Equations) -> String {
    let mut out = String::new();
    line(&mut out, &format!("Equations of {title}"));
    let coordinates: Vec<String> = e.coordinates.iter().map(|(name, unit)| format!("{name} ({unit})")).collect();
    line(&mut out, &format!("\ncoordinates: {}\n", coordinates.join(", ")));
    if !e.poses.is_empty() {
        line(&mut out, "body poses (the joint graph's forward kinematics):");
        let width = e.poses.iter().map(|p| p.body.chars().count()).max().unwrap_or(0);
        for p in &e.poses {
            let pad = " ".repeat(width - p.body.chars().count());
            line(
                &mut out,
                &format!("  {}:{pad}  x = {},  y = {},  φ = {}", p.body, side(&p.x), side(&p.y), side(&p.angle)),
            );
        }
        line(&mut out, "");
    }
    match (&e.kinetic, &e.potential) {
        (Some(t), Some(v)) => {
            line(&mut out, &format!("T = {}", side(t)));
            line(&mut out, &format!("V = {}", side(v)));
            line(&mut out, "L = T − V");
        }
        _ => line(&mut out, &format!("L = {}", side(&e.lagrangian))),
    }
    let constrained = !e.constraints.is_empty();
    line(
        &mut out,
        if constrained {
            "\nLagrange's equations, d/dt ∂L/∂q̇ − ∂L/∂q + Σ λ ∂Φ/∂q = Q (velocity constraints ψ: ∂ψ/∂q̇):"
        } else {
            "\nLagrange's equations, d/dt ∂L/∂q̇ − ∂L/∂q = Q:"
        },
    );
    block(&mut out, &e.equations);
    if constrained {
        line(&mut out, "\nconstraints (multiplier):");
        block(&mut out, &e.constraints);
    }
    if !e.accelerations.is_empty() {
        line(&mut out, "\naccelerations (M constant):");
        for a in &e.accelerations {
            line(&mut out, &format!("  {} = {}", side(&a.left), side(&a.right)));
        }
    }
    if e.conserved_energy.is_some() || !e.conserved_momenta.is_empty() {
        line(&mut out, "\nconstants of the motion:");
        if let Some(h) = &e.conserved_energy {
            line(&mut out, &format!("  E = {}   (L does not depend on t; no generalized force)", side(&h.right)));
        }
        for p in &e.conserved_momenta {
            line(&mut out, &format!("  {} = {}   ({} is cyclic)", side(&p.left), side(&p.right), p.label));
        }
    }
    out
}

fn block(out: &mut String, equations: &[Equation]) {
    let width = equations.iter().map(|e| e.label.chars().count()).max().unwrap_or(0);
    for e in equations {
        let pad = " ".repeat(width - e.label.chars().count());
        line(out, &format!("  {}:{pad}  {} = {}", e.label, side(&e.left), side(&e.right)));
    }
}

/// The equations as one LaTeX `align*` environment.
pub fn latex(e: &Equations) -> String {
    let mut rows = Vec::new();
    for p in &e.poses {
        let body = p.body.replace('_', "\\_");
        rows.push(format!("x_{{\\text{{{body}}}}} &= {}", p.x.latex));
        rows.push(format!("y_{{\\text{{{body}}}}} &= {}", p.y.latex));
        rows.push(format!("\\varphi_{{\\text{{{body}}}}} &= {}", p.angle.latex));
    }
    if let (Some(t), Some(v)) = (&e.kinetic, &e.potential) {
        rows.push(format!("T &= {}", t.latex));
        rows.push(format!("V &= {}", v.latex));
    }
    rows.push(format!("L &= {}", e.lagrangian.latex));
    for eq in e.equations.iter().chain(&e.constraints).chain(&e.accelerations) {
        rows.push(format!("{} &= {}", eq.left.latex, eq.right.latex));
    }
    if let Some(h) = &e.conserved_energy {
        rows.push(format!("E &= {}", h.right.latex));
    }
    for p in &e.conserved_momenta {
        rows.push(format!("{} &= {}", p.left.latex, p.right.latex));
    }
    format!("\\begin{{align*}}\n{}\n\\end{{align*}}\n", rows.join(" \\\\\n"))
}
