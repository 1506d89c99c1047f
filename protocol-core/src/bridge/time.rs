//! Time as the engine sees it: the caller's monotonic clock.
