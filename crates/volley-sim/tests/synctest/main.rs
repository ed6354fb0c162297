//! The sync test: clean runs pass, injected nondeterminism is caught and placed.

mod basics;
mod faults;
mod sweep;
