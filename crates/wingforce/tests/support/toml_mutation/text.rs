//! Text-level mutations of a model file: truncation, a flipped bit, spliced bytes, random
//! bytes, random text and TOML-like text (invalid UTF-8 becomes U+FFFD, as a caller's lossy
//! read would).

use proptest::prelude::*;
use proptest::sample::Index;

#[derive(Debug, Clone)]
pub enum TextMutation {
    Truncate(Index),
    FlipBit(Index, u8),
    Splice(Index, Vec<u8>),
    Garbage(Vec<u8>),
    Text(String),
    Tomlish(String),
}

pub fn text_mutation() -> impl Strategy<Value = TextMutation> {
    prop_oneof![
        3 => any::<Index>().prop_map(TextMutation::Truncate),
        2 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| TextMutation::FlipBit(i, b)),
        2 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..16))
            .prop_map(|(i, b)| TextMutation::Splice(i, b)),
        1 => prop::collection::vec(any::<u8>(), 0..400).prop_map(TextMutation::Garbage),
        1 => any::<String>().prop_map(TextMutation::Text),
        2 => "[\\[\\]=\"'a-z_.0-9 \n#+-]{0,300}".prop_map(TextMutation::Tomlish),
    ]
}

pub fn mutate_text(base: &str, m: &TextMutation) -> String {
    let bytes = base.as_bytes();
    let out: Vec<u8> = match m {
        TextMutation::Truncate(i) => bytes[..i.index(bytes.len() + 1)].to_vec(),
        TextMutation::FlipBit(i, b) => {
            let mut v = bytes.to_vec();
            v[i.index(bytes.len())] ^= 1 << b;
            v
        }
        TextMutation::Splice(i, g) => {
            let at = i.index(bytes.len() + 1);
            let mut v = bytes[..at].to_vec();
            v.extend_from_slice(g);
            v.extend_from_slice(&bytes[at..]);
            v
        }
        TextMutation::Garbage(g) => g.clone(),
        TextMutation::Text(s) | TextMutation::Tomlish(s) => s.clone().into_bytes(),
    };
    // The loaders take text: invalid UTF-8 becomes U+FFFD, as a caller's lossy read would.
    String::from_utf8_lossy(&out).into_owned()
}
