//! Raw HTTP/1.1 for the web servers' tests: requests sent byte for byte (so paths reach the
//! server exactly as written) and replies read back whole.
#![allow(dead_code)]

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::process::{Child, ChildStdout, Command, Output, Stdio};
use std::time::Duration;

/// A reply as it came off the wire.
pub struct Reply {
    pub status: u16,
    pub head: String,
    pub body: Vec<u8>,
}

impl Reply {
    pub fn text(&self) -> String {
        String::from_utf8_lossy(&self.body).into_owned()
    }

    pub fn header(&self, name: &str) -> Option<String> {
        self.head.lines().find_map(|line| {
            let (k, v) = line.split_once(':')?;
            k.eq_ignore_ascii_case(name).then(|| v.trim().to_owned())
        })
    }
}

/// Sends raw bytes (so paths reach the server exactly as written) and reads the reply (a
/// live render may take seconds on a software adapter).
pub fn send(addr: SocketAddr, raw: &[u8]) -> Reply {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    stream.write_all(raw).unwrap();
    let mut bytes = Vec::new();
    stream.read_to_end(&mut bytes).unwrap();
    let split = bytes
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .unwrap_or_else(|| panic!("no HTTP head in {:?}", String::from_utf8_lossy(&bytes)));
    let head = String::from_utf8_lossy(&bytes[..split]).into_owned();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    Reply {
        status,
        head,
        body: bytes[split + 4..].to_vec(),
    }
}

pub fn get(addr: SocketAddr, target: &str) -> Reply {
    let host = format!("127.0.0.1:{}", addr.port());
    send(
        addr,
        format!("GET {target} HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n").as_bytes(),
    )
}

/// A server command (`omnicloud view` or `omnicloud serve`) running with piped output, past
/// the line that gives its address.
pub struct ServerProcess {
    child: Child,
    stdout: BufReader<ChildStdout>,
    /// The lines it printed before the address.
    pub before: Vec<String>,
    /// The address of its `open http://ADDR/` line.
    pub addr: SocketAddr,
}

impl ServerProcess {
    /// Starts `command` and reads its stdout up to the `open http://ADDR/` line.
    pub fn start(mut command: Command) -> ServerProcess {
        let mut child = command
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(child.stdout.take().unwrap());
        let mut before = Vec::new();
        let url = loop {
            let mut line = String::new();
            assert!(
                stdout.read_line(&mut line).unwrap() > 0,
                "no address in {before:?}"
            );
            if let Some(rest) = line.strip_prefix("open http://") {
                break rest.split('/').next().unwrap().to_owned();
            }
            before.push(line);
        };
        ServerProcess {
            child,
            stdout,
            before,
            addr: url.parse().unwrap(),
        }
    }

    /// Stops the server with Ctrl-C (SIGINT), checks it exited successfully, and returns its
    /// output: the rest of its stdout and all its stderr.
    #[cfg(unix)]
    pub fn interrupt(mut self) -> Output {
        let status = Command::new("kill")
            .args(["-INT", &self.child.id().to_string()])
            .status()
            .unwrap();
        assert!(status.success());
        let mut out = self.child.wait_with_output().unwrap();
        assert!(out.status.success(), "{out:?}");
        self.stdout.read_to_end(&mut out.stdout).unwrap();
        out
    }
}
