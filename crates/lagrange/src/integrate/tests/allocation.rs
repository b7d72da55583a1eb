//! No heap allocation per step of the implicit integrators, nor per Jacobian (a counting global
//! allocator, as in the integration tests' `allocation` check, for this crate's unit tests).
#![allow(unsafe_code)] // a global allocator is necessarily `unsafe impl`

use crate::dynamics::tests::WithoutJacobian;
use crate::integrate::{Gauss4, Sdirk4, Tolerances};
use crate::test_support::{Cart, Charge, Driven, RodChain, Spring};
use crate::{Coordinate, Dynamics, Model, RawModel, State};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    /// Allocations made by this thread (tests run in parallel threads).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

fn count() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: forwards every call unchanged to the system allocator; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

/// Jacobians, Gauss4 steps and Sdirk4 steps allocate nothing once their buffers exist.
fn assert_no_allocation<D: Dynamics>(name: &str, system: &D, initial: &State) {
    let n = system.dof();
    let mut ws = system.new_workspace();
    let mut jacobian = vec![0.0; 2 * n * n];
    let mut gauss = Gauss4::new(n);
    let mut state = initial.clone();
    let mut sdirk = Sdirk4::new(n, Tolerances::uniform(1e-8)).expect("valid");
    sdirk.start(system, &mut ws, initial.t, &initial.q, &initial.qdot, 1.0).expect("valid");
    // Warm-up: anything lazily initialised happens here, outside the count.
    system.acceleration_jacobian(&mut ws, initial.t, &initial.q, &initial.qdot, &mut jacobian).expect("valid");
    gauss.step(system, &mut ws, &mut state, 1e-3).expect("valid");
    let counted = allocations(|| {
        for _ in 0..10 {
            system.acceleration_jacobian(&mut ws, initial.t, &initial.q, &initial.qdot, &mut jacobian).expect("valid");
            gauss.step(system, &mut ws, &mut state, 1e-3).expect("valid");
            sdirk.step(system, &mut ws, 1e9).expect("valid");
        }
    });
    assert_eq!(counted, 0, "{name}: {counted} heap allocations in 10 steps");
    assert!(gauss.stats.jacobians > 0 && sdirk.stats.jacobians > 0 && sdirk.stats.accepted == 10);
}

#[test]
fn implicit_steps_and_jacobians_allocate_nothing() {
    let cart = State::new(0.0, [0.1, 0.5], [0.2, -0.3]);
    assert_no_allocation("cart pendulum", &Model::new(Cart::new(2.0, 1.0, 1.0)).unwrap(), &cart);
    let chain = RodChain::new(&[1.0, 0.7, 1.4], &[1.0, 0.8, 0.6], 9.81);
    let chain_state = State::new(0.0, [0.3, -0.2, 0.5], [0.1, 0.0, -0.4]);
    assert_no_allocation("rod chain (tree path)", &Model::new(chain.clone()).unwrap(), &chain_state);
    assert_no_allocation("rod chain (assembled)", &Model::new_generic(chain).unwrap(), &chain_state);
    let spring = State::new(0.0, [0.1], [0.0]);
    assert_no_allocation("damped oscillator", &Model::new(Spring::new(1.0, 10.0, 0.5)).unwrap(), &spring);
    let driven = State::new(0.3, [0.2], [0.1]);
    assert_no_allocation("driven pendulum", &Model::new(Driven::new()).unwrap(), &driven);
    let raw = RawModel::new(Model::new(Cart::new(2.0, 1.0, 1.0)).unwrap()).unwrap();
    assert_no_allocation("cart pendulum (raw path)", &raw, &cart);
    let charge =
        RawModel::new(Charge { coordinates: [Coordinate::length("x"), Coordinate::length("y")], m: 2.0, e_b: 3.0 })
            .unwrap();
    assert_no_allocation("charge (raw path)", &charge, &State::new(0.0, [0.3, -0.2], [0.7, 1.1]));
    // The counter counts: the finite-difference default allocates its work vectors.
    let fallback = WithoutJacobian(Model::new(Cart::new(2.0, 1.0, 1.0)).unwrap());
    let mut ws = fallback.new_workspace();
    let mut jacobian = [0.0; 8];
    let counted = allocations(|| {
        fallback.acceleration_jacobian(&mut ws, 0.0, &cart.q, &cart.qdot, &mut jacobian).expect("valid");
    });
    assert!(counted >= 4, "{counted}");
}
