//! The spanning tree of a joint graph and its orientation from the ground: which joints place
//! bodies (the tree) and which close loops, and in what order forward kinematics visits them.
//! Nodes are the ground (0) and the bodies (`b + 1` for body `b`); a joint's ends are body
//! indices, `None` for the ground.

use super::description::{JointGraph, Role};
use super::invalid;
use crate::Error;

/// A joint's two ends: parent and child body (`None`: the ground).
pub(super) type Ends = (Option<usize>, Option<usize>);

/// The node of a joint's end.
fn node(end: Option<usize>) -> usize {
    end.map_or(0, |b| b + 1)
}

/// Union-find root of `i`, halving the path on the way.
fn root(sets: &mut [usize], mut i: usize) -> usize {
    while sets[i] != i {
        sets[i] = sets[sets[i]];
        i = sets[i];
    }
    i
}

/// Which joints form the spanning tree (Kruskal's method on a union-find): the joints marked
/// [`Role::Tree`] first, then the others in the order listed, each unless it closes a loop.
///
/// # Errors
/// [`Error::InvalidGraph`] for tree-marked joints that close a loop among themselves, or a
/// body with no path of joints to the ground.
pub(super) fn spanning_tree(graph: &JointGraph, ends: &[Ends]) -> Result<Vec<bool>, Error> {
    let mut sets: Vec<usize> = (0..=graph.bodies.len()).collect();
    let mut in_tree = vec![false; ends.len()];
    for pass in [Role::Tree, Role::Auto] {
        for (j, joint) in graph.joints.iter().enumerate().filter(|(_, joint)| joint.role == pass) {
            let (a, b) = (root(&mut sets, node(ends[j].0)), root(&mut sets, node(ends[j].1)));
            if a == b {
                if pass == Role::Tree {
                    return Err(invalid(
                        &format!("joint `{}`", joint.name),
                        "is marked as a tree joint but closes a loop of tree joints".into(),
                    ));
                }
                continue;
            }
            sets[a] = b;
            in_tree[j] = true;
        }
    }
    for (b, body) in graph.bodies.iter().enumerate() {
        if root(&mut sets, b + 1) != root(&mut sets, 0) {
            return Err(invalid(&format!("body `{}`", body.name), "has no path of joints to the ground".into()));
        }
    }
    Ok(in_tree)
}

/// The spanning tree oriented from the ground.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Orientation {
    /// Per joint: a tree joint that hangs its parent from its child (the child is nearer the
    /// ground).
    pub reversed: Vec<bool>,
    /// Forward kinematics: `(joint, body it places)`, every body once, parents first.
    pub order: Vec<(usize, usize)>,
    /// The tree joints from the ground to each body, in order.
    pub paths: Vec<Vec<usize>>,
}

/// Orient the tree from the ground, breadth first, visiting the joints at each node in the
/// order listed: `O(bodies + joints)` from the nodes' lists of tree joints.
pub(super) fn orient(bodies: usize, ends: &[Ends], in_tree: &[bool]) -> Orientation {
    let mut adjacent: Vec<Vec<usize>> = vec![Vec::new(); bodies + 1];
    for (j, &(p, c)) in ends.iter().enumerate().filter(|(j, _)| in_tree[*j]) {
        adjacent[node(p)].push(j);
        adjacent[node(c)].push(j);
    }
    let mut placed = vec![false; bodies];
    let mut reversed = vec![false; ends.len()];
    let mut order = Vec::with_capacity(bodies);
    let mut paths: Vec<Vec<usize>> = vec![Vec::new(); bodies];
    let mut frontier: Vec<Option<usize>> = vec![None];
    while !frontier.is_empty() {
        let mut next = Vec::new();
        for known in frontier {
            for &j in &adjacent[node(known)] {
                let (p, c) = ends[j];
                let body = if p == known && c.is_some_and(|c| !placed[c]) {
                    c
                } else if c == known && p.is_some_and(|p| !placed[p]) {
                    reversed[j] = true;
                    p
                } else {
                    continue;
                };
                let Some(body) = body else { continue };
                placed[body] = true;
                let mut path = known.map_or_else(Vec::new, |k| paths[k].clone());
                path.push(j);
                paths[body] = path;
                order.push((j, body));
                next.push(Some(body));
            }
        }
        frontier = next;
    }
    Orientation { reversed, order, paths }
}
