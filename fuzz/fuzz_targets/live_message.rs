//! The live stream's messages: a client's pose (JSON text, checked against the scan) and the
//! server's frame message (length-prefixed JSON header, then the image) as a client splits it.
#![no_main]

use glam::DVec2;
use omnicloud::web::serve::CameraLimits;
use omnicloud::web::serve::live::pose::MAX_POSE_BYTES;
use omnicloud::web::serve::live::{PoseError, PoseLimits, frame_message, parse_pose, split_frame};

const LIMITS: PoseLimits = PoseLimits {
    xy: CameraLimits {
        lo: DVec2::new(-50.0, 100.0),
        hi: DVec2::new(150.0, 300.0),
        default: DVec2::new(10.0, 200.0),
    },
    z: (-5.0, 40.0),
    per_metre: 1.0,
};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data)
        && text.len() <= MAX_POSE_BYTES
    {
        pose(text);
    }
    frame(data);
});

fn pose(text: &str) {
    match parse_pose(text, &LIMITS) {
        Ok(p) => {
            let r = &p.request;
            assert!(
                (LIMITS.xy.lo.x..=LIMITS.xy.hi.x).contains(&r.xy.x)
                    && (LIMITS.xy.lo.y..=LIMITS.xy.hi.y).contains(&r.xy.y),
                "{p:?}"
            );
            assert!(
                r.z.is_none_or(|z| (LIMITS.z.0..=LIMITS.z.1).contains(&z)),
                "{p:?}"
            );
            assert!(r.height.is_none_or(f64::is_finite), "{p:?}");
            assert!(r.ipd.is_finite() && r.ipd >= 0.0, "{p:?}");
            assert!((0.0..360.0).contains(&p.yaw), "{p:?}");
            assert!((-90.0..=90.0).contains(&p.pitch), "{p:?}");
        }
        Err(e) => {
            assert!(matches!(e.close_code(), 1007 | 1008));
            assert!(!e.to_string().is_empty());
            if let PoseError::Outside(m) = &e {
                assert!(m.contains("within the scan"), "{m}");
            }
        }
    }
}

fn frame(data: &[u8]) {
    let Ok((header, image)) = split_frame(data) else {
        return;
    };
    let message = frame_message(&header, image);
    let (again, image_again) = split_frame(&message).expect("a message made here splits");
    assert_eq!(image_again, image);
    assert_eq!(
        (
            again.seq,
            again.width,
            again.height,
            &again.format,
            again.quality,
            again.still
        ),
        (
            header.seq,
            header.width,
            header.height,
            &header.format,
            header.quality,
            header.still
        )
    );
}
