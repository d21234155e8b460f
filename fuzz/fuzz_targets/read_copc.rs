//! COPC bytes: the info VLR and hierarchy EVLR ([`read_octree`]), then the chunks of the nodes
//! it lists ([`open_nodes`]), as a level-of-detail render reads them.
#![no_main]

mod common;

use omnicloud::io::{NodeKey, open_nodes, read_octree};

/// Points decoded per input, smallest nodes first (at least one node): every node's chunk
/// goes through the same decoder, and small ones keep an execution short.
const POINT_BUDGET: u64 = 1024;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let Some(path) = common::scratch_file("input.copc.laz", data) else {
        return;
    };
    let Ok(octree) = read_octree(&path) else {
        return;
    };
    assert!(octree.halfsize > 0.0 && octree.spacing > 0.0 && octree.center.is_finite());
    let _ = octree.depth();
    let mut by_size: Vec<(u64, NodeKey)> = octree.nodes.iter().map(|(k, n)| (*n, *k)).collect();
    by_size.sort_unstable();
    for (_, key) in &by_size {
        let (lo, hi) = octree.bounds(*key);
        assert!(lo.is_finite() && hi.is_finite(), "{key:?}: {lo} {hi}");
        let _ = octree.has_children(*key);
        let _ = octree.child_at(*key, (lo + hi) * 0.5);
    }
    let mut budget = 0u64;
    let keys: Vec<NodeKey> = by_size
        .iter()
        .take_while(|(n, _)| {
            budget = budget.saturating_add(*n);
            budget <= POINT_BUDGET
        })
        .map(|(_, k)| *k)
        .collect();
    let keys = if keys.is_empty() {
        vec![by_size[0].1]
    } else {
        keys
    };
    if let Ok(reader) = open_nodes(&path, &keys) {
        for chunk in reader.chunks(4096) {
            if chunk.is_err() {
                break;
            }
        }
    }
});
