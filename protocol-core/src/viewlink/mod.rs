//! The Viewlink (Viewpro) serial protocol V3.4.4 (`004_97d9a16052f5b223.txt`).
//!
//! Not implemented yet (issue 3).
