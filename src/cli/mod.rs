//! Subcommands, one file each (as cargo's `commands/`); main.rs parses the command line and
//! dispatches. New subcommands go here (`info`, `convert`); the older ones move here as they are
//! next changed.

pub mod convert;
pub mod info;
