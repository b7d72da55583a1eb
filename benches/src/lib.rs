//! Benchmarks only: see `eom.rs` (`cargo bench -p lagrange-benches`).
