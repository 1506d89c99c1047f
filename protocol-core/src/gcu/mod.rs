//! The XF Robot GCU private protocol V2.0.2 (`001_8e19e435fc647e3e.txt`).
//!
//! Not implemented yet (issue 4).
