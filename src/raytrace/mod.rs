//! CPU ray tracer: the exact accuracy reference (obvhs BVH over spheres).
