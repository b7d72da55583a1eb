//! Examples only: see `quickstart.rs` (`cargo run -p lagrange-examples --example quickstart`).
