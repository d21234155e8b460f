// Mirrors src/projection/camera.rs: the camera's orthonormal frame (DESIGN §1).

struct Basis {
    forward: vec3<f32>,
    right: vec3<f32>,
    up: vec3<f32>,
}
