//! The sync test: clean runs pass, injected nondeterminism is caught and placed.

mod basics;
mod faults;
#[path = "../../../../benches/common/splice.rs"]
mod splice;
mod sweep;
