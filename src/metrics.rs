//! Image error metrics.
