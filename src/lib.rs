pub mod accel;
pub mod image_io;
pub mod metrics;
pub mod scene;
