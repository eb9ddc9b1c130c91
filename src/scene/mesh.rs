//! OBJ meshes and shape tessellation.
