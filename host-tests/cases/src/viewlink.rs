//! viewlink codec cases (none yet).

cases!("viewlink":);
