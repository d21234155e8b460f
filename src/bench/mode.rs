//! The rasterizer modes a benchmark compares: every proxy × every imposter.

use serde::{Deserialize, Serialize};

use crate::render::{Imposter, Proxy};

/// One rasterizer mode: proxy geometry and fragment model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BenchMode {
    /// Proxy geometry.
    pub proxy: Proxy,
    /// Fragment model.
    pub imposter: Imposter,
}

/// The proxies of the paper's Table 1 (No Tess., Static 4, Static 16, Dynamic) plus `bounds`,
/// in column order.
pub const TABLE_PROXIES: [Proxy; 5] = [
    Proxy::Quad,
    Proxy::Static(4),
    Proxy::Static(16),
    Proxy::Dynamic,
    Proxy::Bounds,
];

/// Both fragment models, in row order.
pub const TABLE_IMPOSTERS: [Imposter; 2] = [Imposter::Sprite, Imposter::Raycast];

impl BenchMode {
    /// Every proxy of [`TABLE_PROXIES`] with every imposter (10 modes), sprite first.
    pub fn all() -> Vec<BenchMode> {
        TABLE_IMPOSTERS
            .iter()
            .flat_map(|&imposter| {
                TABLE_PROXIES
                    .iter()
                    .map(move |&proxy| BenchMode { proxy, imposter })
            })
            .collect()
    }

    /// The CLI spelling of the proxy: `quad`, `static:N`, `dynamic`, `bounds`.
    pub fn proxy_name(&self) -> String {
        proxy_name(self.proxy)
    }

    /// The CLI spelling of the imposter: `sprite` or `raycast`.
    pub fn imposter_name(&self) -> &'static str {
        imposter_name(self.imposter)
    }

    /// `proxy+imposter`, e.g. `static:4+sprite`.
    pub fn label(&self) -> String {
        format!("{}+{}", self.proxy_name(), self.imposter_name())
    }

    /// Parses a label written by [`BenchMode::label`] (or `proxy` alone, meaning raycast).
    pub fn parse(s: &str) -> Result<BenchMode, String> {
        let (p, i) = s.split_once('+').unwrap_or((s, "raycast"));
        Ok(BenchMode {
            proxy: p.parse()?,
            imposter: i.parse()?,
        })
    }
}

/// The paper's column heading for a proxy.
pub fn proxy_heading(p: Proxy) -> String {
    match p {
        Proxy::Quad => "No Tess.".to_string(),
        Proxy::Static(n) => format!("Static ({n})"),
        Proxy::Dynamic => "Dynamic".to_string(),
        Proxy::Bounds => "Bounds (ours)".to_string(),
    }
}

/// The CLI spelling of a proxy.
pub fn proxy_name(p: Proxy) -> String {
    match p {
        Proxy::Quad => "quad".to_string(),
        Proxy::Static(n) => format!("static:{n}"),
        Proxy::Dynamic => "dynamic".to_string(),
        Proxy::Bounds => "bounds".to_string(),
    }
}

/// The CLI spelling of an imposter.
pub fn imposter_name(i: Imposter) -> &'static str {
    match i {
        Imposter::Sprite => "sprite",
        Imposter::Raycast => "raycast",
    }
}

impl Serialize for BenchMode {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.label())
    }
}

impl<'de> Deserialize<'de> for BenchMode {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        BenchMode::parse(&s).map_err(serde::de::Error::custom)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_distinct_modes_whose_labels_parse_back() {
        let all = BenchMode::all();
        assert_eq!(all.len(), 10);
        for m in &all {
            assert_eq!(BenchMode::parse(&m.label()).unwrap(), *m);
        }
        assert_eq!(all[0].label(), "quad+sprite");
        assert_eq!(all[9].label(), "bounds+raycast");
    }
}
