//! siyi codec cases (none yet).

cases!("siyi":);
