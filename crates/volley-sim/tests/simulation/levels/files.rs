//! Level files in scenes: readers, errors, content hashes, round trips.
