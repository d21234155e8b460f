//! The render queue: one waiting job per client, and a newer job of a client replaces its
//! waiting one, so a slider dragged faster than frames render ends on its last value, never
//! on a stale one. Clients number their jobs; browsers may send requests out of order, so a
//! job older than the client's waiting or last taken job is refused rather than queued.

use std::collections::{HashMap, VecDeque};
use std::hash::Hash;
use std::sync::{Condvar, Mutex, PoisonError};

/// Clients remembered for refusing stale jobs; past this many the memory starts afresh.
const MAX_CLIENTS: usize = 1024;

/// Waiting jobs in arrival order, at most one per client key.
pub struct LatestQueue<K, T> {
    state: Mutex<State<K, T>>,
    ready: Condvar,
}

struct State<K, T> {
    waiting: VecDeque<(K, u64, T)>,
    /// The sequence number of each client's last taken job.
    taken: HashMap<K, u64>,
    closed: bool,
}

impl<K: Eq + Hash + Clone, T> Default for LatestQueue<K, T> {
    fn default() -> Self {
        LatestQueue {
            state: Mutex::new(State {
                waiting: VecDeque::new(),
                taken: HashMap::new(),
                closed: false,
            }),
            ready: Condvar::new(),
        }
    }
}

impl<K: Eq + Hash + Clone, T> LatestQueue<K, T> {
    /// An empty, open queue.
    pub fn new() -> Self {
        Self::default()
    }

    /// Queues `job`, number `seq` of client `key`, and returns the job that will not be
    /// taken: the client's waiting job when `job` is at least as new (equal numbers: the
    /// later arrival wins), else `job` itself (older than what the client already has
    /// waiting or taken, or the queue is closed). Number 0 is unnumbered: never older than
    /// anything, so it always replaces the client's waiting job.
    pub fn push(&self, key: K, seq: u64, job: T) -> Option<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        let stale = |than: u64| seq != 0 && seq < than;
        if state.closed || state.taken.get(&key).is_some_and(|&last| stale(last)) {
            return Some(job);
        }
        if let Some(slot) = state.waiting.iter_mut().find(|(k, _, _)| *k == key) {
            if stale(slot.1) {
                return Some(job);
            }
            let (_, _, old) = std::mem::replace(slot, (key, seq, job));
            return Some(old);
        }
        state.waiting.push_back((key, seq, job));
        self.ready.notify_one();
        None
    }

    /// Waits for the longest-waiting job and takes it; `None` once the queue is closed.
    pub fn take(&self) -> Option<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        loop {
            if state.closed {
                return None;
            }
            if let Some((key, seq, job)) = state.waiting.pop_front() {
                if state.taken.len() >= MAX_CLIENTS {
                    state.taken.clear();
                }
                state.taken.insert(key, seq);
                return Some(job);
            }
            state = self
                .ready
                .wait(state)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Closes the queue: [`take`](Self::take) returns `None`; the waiting jobs are handed
    /// back.
    pub fn close(&self) -> Vec<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        state.closed = true;
        self.ready.notify_all();
        state.waiting.drain(..).map(|(_, _, job)| job).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::time::Duration;

    #[test]
    fn a_newer_job_replaces_the_waiting_one_and_an_older_one_is_refused() {
        let q = LatestQueue::new();
        assert_eq!(q.push("a", 1, "a1"), None);
        assert_eq!(q.push("a", 3, "a3"), Some("a1"));
        // Sent before a3, arrived after it.
        assert_eq!(q.push("a", 2, "a2"), Some("a2"));
        assert_eq!(q.take(), Some("a3"));
        assert_eq!(
            q.push("a", 2, "late"),
            Some("late"),
            "older than the one taken"
        );
        assert_eq!(q.push("a", 3, "again"), None, "as new as the one taken");
        assert_eq!(q.close(), vec!["again"]);
        assert_eq!(q.take(), None);
        assert_eq!(q.push("a", 9, "closed"), Some("closed"));
    }

    #[test]
    fn each_client_keeps_its_own_waiting_job_in_arrival_order() {
        let q = LatestQueue::new();
        assert_eq!(q.push("desk", 5, "d5"), None);
        assert_eq!(q.push("headset", 1, "h1"), None);
        assert_eq!(q.push("desk", 6, "d6"), Some("d5"));
        // Unnumbered requests (0): the later arrival wins, whatever came before.
        assert_eq!(q.push("", 7, "w"), None);
        assert_eq!(q.push("", 0, "x"), Some("w"));
        assert_eq!(q.push("", 0, "y"), Some("x"));
        assert_eq!(q.take(), Some("d6"));
        assert_eq!(q.take(), Some("h1"));
        assert_eq!(q.take(), Some("y"));
        assert_eq!(q.push("desk", 0, "d0"), None, "after d6 was taken");
    }

    #[test]
    fn a_slow_consumer_sees_the_newest_job_and_drops_the_rest() {
        let q = Arc::new(LatestQueue::new());
        let (taken_tx, taken_rx) = std::sync::mpsc::channel();
        let consumer = {
            let q = q.clone();
            std::thread::spawn(move || {
                while let Some(job) = q.take() {
                    taken_tx.send(job).unwrap();
                    // A render that outlasts the requests arriving meanwhile.
                    std::thread::sleep(Duration::from_millis(50));
                }
            })
        };
        let mut dropped = Vec::new();
        for job in 0..20 {
            dropped.extend(q.push("page", job, job));
            std::thread::sleep(Duration::from_millis(5));
        }
        // Let the consumer finish what it holds and take the last job.
        let mut taken: Vec<u64> = Vec::new();
        while taken.last() != Some(&19) {
            taken.push(taken_rx.recv_timeout(Duration::from_secs(5)).unwrap());
        }
        q.close();
        consumer.join().unwrap();
        // Every job was either taken or handed back, never both; the last taken is the newest.
        let mut all: Vec<u64> = taken.iter().chain(&dropped).copied().collect();
        all.sort_unstable();
        assert_eq!(all, (0..20).collect::<Vec<_>>());
        assert!(taken.windows(2).all(|w| w[0] < w[1]), "{taken:?}");
        assert!(taken.len() < 10, "a slow consumer skips most: {taken:?}");
    }
}
