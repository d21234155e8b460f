// Mirrors src/projection/camera.rs: the camera's orthonormal frame (DESIGN §1).

struct Basis {
    forward: vec3<f32>,
    right: vec3<f32>,
    up: vec3<f32>,
}

// Forward, right and up vectors for heading `yaw_deg` (0 looks along +Y).
fn camera_basis(yaw_deg: f32) -> Basis {
    let yaw = radians(yaw_deg);
    let forward = vec3<f32>(sin(yaw), cos(yaw), 0.0);
    let up = vec3<f32>(0.0, 0.0, 1.0);
    return Basis(forward, cross(forward, up), up);
}
