//! The SIYI gimbal camera SDK protocol (`003_d4f397a57e673bf9.txt`, `siyi-commands.md`).
//!
//! Not implemented yet (issue 5).
