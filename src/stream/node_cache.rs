//! A cache of level-of-detail nodes bounded by their size in bytes: what a frame reads stays
//! for the next frames, and the least recently used nodes leave first when a new one needs
//! the room.

use std::collections::HashMap;
use std::hash::Hash;

/// What a cache did, for the summary and for tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CacheCounts {
    /// Look-ups that found their node.
    pub hits: u64,
    /// Look-ups that did not.
    pub misses: u64,
    /// Nodes inserted.
    pub inserted: u64,
    /// Nodes evicted to make room.
    pub evicted: u64,
    /// Nodes refused because alone they exceed the budget.
    pub refused: u64,
}

/// One node held, with its size and when it was last used.
struct Entry<V> {
    value: V,
    bytes: u64,
    last_used: u64,
}

/// Values keyed by node, at most `budget` bytes together; see the module docs.
pub struct NodeCache<K, V> {
    budget: u64,
    used: u64,
    clock: u64,
    entries: HashMap<K, Entry<V>>,
    counts: CacheCounts,
}

impl<K: Eq + Hash + Copy, V> NodeCache<K, V> {
    /// An empty cache holding at most `budget` bytes.
    pub fn new(budget: u64) -> Self {
        NodeCache {
            budget,
            used: 0,
            clock: 0,
            entries: HashMap::new(),
            counts: CacheCounts::default(),
        }
    }

    /// The bound, bytes.
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// Bytes held.
    pub fn used(&self) -> u64 {
        self.used
    }

    /// Nodes held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when no node is held.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// What the cache did so far.
    pub fn counts(&self) -> CacheCounts {
        self.counts
    }

    /// True when `key` is held (not a use: the order of eviction stays).
    pub fn contains(&self, key: &K) -> bool {
        self.entries.contains_key(key)
    }

    /// The node of `key` if held, without marking it used.
    pub fn peek(&self, key: &K) -> Option<&V> {
        self.entries.get(key).map(|e| &e.value)
    }

    /// The node of `key`, marked as just used; `None` (a miss) when not held.
    pub fn get(&mut self, key: &K) -> Option<&V> {
        self.clock += 1;
        match self.entries.get_mut(key) {
            Some(entry) => {
                entry.last_used = self.clock;
                self.counts.hits += 1;
                Some(&entry.value)
            }
            None => {
                self.counts.misses += 1;
                None
            }
        }
    }

    /// Drops every node held (their counts stay).
    pub fn clear(&mut self) {
        self.entries.clear();
        self.used = 0;
    }

    /// Holds `value` of `bytes` under `key` (replacing an older one), evicting the least
    /// recently used nodes until it fits. A value larger than the whole budget is not held
    /// and comes back as `Err` for the caller to use once.
    pub fn insert(&mut self, key: K, value: V, bytes: u64) -> Result<&V, V> {
        if let Some(old) = self.entries.remove(&key) {
            self.used -= old.bytes;
        }
        if bytes > self.budget {
            self.counts.refused += 1;
            return Err(value);
        }
        while self.used + bytes > self.budget {
            let oldest = self
                .entries
                .iter()
                .min_by_key(|(_, e)| e.last_used)
                .map(|(k, _)| *k);
            let Some(oldest) = oldest else { break };
            if let Some(e) = self.entries.remove(&oldest) {
                self.used -= e.bytes;
                self.counts.evicted += 1;
            }
        }
        self.clock += 1;
        self.used += bytes;
        self.counts.inserted += 1;
        let entry = self.entries.entry(key).insert_entry(Entry {
            value,
            bytes,
            last_used: self.clock,
        });
        Ok(&entry.into_mut().value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_least_recently_used_node_leaves_first_and_the_bound_holds() {
        let mut cache: NodeCache<u32, &str> = NodeCache::new(100);
        cache.insert(1, "a", 40).unwrap();
        cache.insert(2, "b", 40).unwrap();
        // Using 1 makes 2 the oldest.
        assert_eq!(cache.get(&1), Some(&"a"));
        cache.insert(3, "c", 40).unwrap();
        assert!(cache.contains(&1) && cache.contains(&3) && !cache.contains(&2));
        assert_eq!(cache.used(), 80);
        assert_eq!(cache.get(&2), None);
        // 90 bytes need both others out.
        cache.insert(4, "d", 90).unwrap();
        assert_eq!(cache.len(), 1);
        assert_eq!(cache.used(), 90);
        let counts = cache.counts();
        assert_eq!(
            (counts.hits, counts.misses, counts.inserted, counts.evicted),
            (1, 1, 4, 3)
        );
    }

    #[test]
    fn a_node_larger_than_the_budget_is_handed_back() {
        let mut cache: NodeCache<u32, Vec<u8>> = NodeCache::new(10);
        cache.insert(1, vec![1], 5).unwrap();
        assert_eq!(cache.insert(2, vec![2; 11], 11), Err(vec![2; 11]));
        assert!(cache.contains(&1));
        assert_eq!((cache.used(), cache.counts().refused), (5, 1));
        cache.clear();
        assert!(cache.is_empty() && !cache.contains(&1));
        assert_eq!((cache.used(), cache.counts().inserted), (0, 1));
    }

    #[test]
    fn replacing_a_key_frees_its_old_bytes() {
        let mut cache: NodeCache<u32, u8> = NodeCache::new(10);
        cache.insert(1, 1, 8).unwrap();
        cache.insert(1, 2, 9).unwrap();
        assert_eq!(
            (cache.used(), cache.len(), cache.counts().evicted),
            (9, 1, 0)
        );
        assert_eq!(cache.get(&1), Some(&2));
    }

    #[test]
    fn a_long_walk_never_exceeds_the_bound() {
        let mut cache: NodeCache<u32, ()> = NodeCache::new(1000);
        for k in 0..500u32 {
            let bytes = u64::from(k % 7 + 1) * 37;
            if cache.get(&(k % 40)).is_none() {
                cache.insert(k % 40, (), bytes).unwrap();
            }
            assert!(cache.used() <= 1000);
        }
        assert!(cache.counts().evicted > 0);
        assert_eq!(
            cache.counts().inserted - cache.counts().evicted,
            cache.len() as u64
        );
    }
}
