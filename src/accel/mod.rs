//! Acceleration structures built on the host: the BVH over scene primitives and the hashed
//! grid over visible points.
