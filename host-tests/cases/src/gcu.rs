//! gcu codec cases (none yet).

cases!("gcu":);
