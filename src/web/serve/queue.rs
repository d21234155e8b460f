//! A render queue of one: a newer request replaces the one still waiting, so a slider
//! dragged faster than frames render is drawn at its latest value, never a stale one last.

use std::sync::{Condvar, Mutex, PoisonError};

/// One waiting job at most; [`push`](Self::push) hands back the job it replaced so the
/// caller can tell its sender.
pub struct LatestQueue<T> {
    state: Mutex<State<T>>,
    ready: Condvar,
}

struct State<T> {
    waiting: Option<T>,
    closed: bool,
}

impl<T> Default for LatestQueue<T> {
    fn default() -> Self {
        LatestQueue {
            state: Mutex::new(State {
                waiting: None,
                closed: false,
            }),
            ready: Condvar::new(),
        }
    }
}

impl<T> LatestQueue<T> {
    /// An empty, open queue.
    pub fn new() -> Self {
        Self::default()
    }

    /// Queues `job` in place of the waiting one, which it returns. After [`close`]
    /// (Self::close) the job itself comes back: nothing will take it.
    pub fn push(&self, job: T) -> Option<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        if state.closed {
            return Some(job);
        }
        let replaced = state.waiting.replace(job);
        self.ready.notify_one();
        replaced
    }

    /// Waits for a job and takes it; `None` once the queue is closed.
    pub fn take(&self) -> Option<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        loop {
            if state.closed {
                return None;
            }
            if let Some(job) = state.waiting.take() {
                return Some(job);
            }
            state = self
                .ready
                .wait(state)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Closes the queue: [`take`](Self::take) returns `None` and the waiting job, if any, is
    /// handed back.
    pub fn close(&self) -> Option<T> {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        state.closed = true;
        self.ready.notify_all();
        state.waiting.take()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::time::Duration;

    #[test]
    fn a_newer_job_replaces_the_waiting_one() {
        let q = LatestQueue::new();
        assert_eq!(q.push(1), None);
        assert_eq!(q.push(2), Some(1));
        assert_eq!(q.push(3), Some(2));
        assert_eq!(q.take(), Some(3));
        assert_eq!(q.push(4), None, "the taken job is no longer waiting");
        assert_eq!(q.close(), Some(4));
        assert_eq!(q.take(), None);
        assert_eq!(q.push(5), Some(5), "a closed queue takes nothing");
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
            dropped.extend(q.push(job));
            std::thread::sleep(Duration::from_millis(5));
        }
        // Let the consumer finish what it holds and take the last job.
        let mut taken: Vec<i32> = Vec::new();
        while taken.last() != Some(&19) {
            taken.push(taken_rx.recv_timeout(Duration::from_secs(5)).unwrap());
        }
        q.close();
        consumer.join().unwrap();
        // Every job was either taken or handed back, never both; the last taken is the newest.
        let mut all: Vec<i32> = taken.iter().chain(&dropped).copied().collect();
        all.sort_unstable();
        assert_eq!(all, (0..20).collect::<Vec<_>>());
        assert!(taken.windows(2).all(|w| w[0] < w[1]), "{taken:?}");
        assert!(taken.len() < 10, "a slow consumer skips most: {taken:?}");
    }
}
