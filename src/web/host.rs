//! The `Host` header check of a server bound to loopback.
//!
//! A web page elsewhere can point a name it controls at 127.0.0.1 (DNS rebinding) and then
//! read a local server as if it were its own origin. Its requests carry that name in `Host`,
//! so a loopback server answers only requests addressed to a loopback name or address.

use std::net::IpAddr;

/// Whether a loopback-bound server should answer a request with this `Host` header.
pub fn loopback_host(host: Option<&str>) -> bool {
    let Some(host) = host else {
        // HTTP/1.0 clients may send none; a browser always sends one.
        return true;
    };
    let name = match host.strip_prefix('[') {
        // [::1]:8360
        Some(rest) => rest.split(']').next().unwrap_or(""),
        None => host.rsplit_once(':').map_or(host, |(name, _port)| name),
    };
    name.eq_ignore_ascii_case("localhost")
        || name.parse::<IpAddr>().is_ok_and(|ip| ip.is_loopback())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loopback_names_pass_and_others_do_not() {
        for ok in [
            Some("127.0.0.1:8360"),
            Some("localhost:8360"),
            Some("LOCALHOST"),
            Some("[::1]:8360"),
            Some("127.0.0.2"),
            None,
        ] {
            assert!(loopback_host(ok), "{ok:?}");
        }
        for bad in [
            Some("evil.example:8360"),
            Some("192.168.1.5:8360"),
            Some("localhost.evil.example"),
            Some(""),
        ] {
            assert!(!loopback_host(bad), "{bad:?}");
        }
    }
}
