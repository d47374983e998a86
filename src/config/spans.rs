//! Where a message points in the TOML text (line and column of a key, the dotted key at an
//! offset) and how a user's value is echoed in it.

use super::*;

/// `s` cut to 40 characters for echoing in a message.
pub fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}...", s.chars().take(40).collect::<String>())
    }
}

/// A `[board.pins]` value as TOML text: "Y6" or ["A1", "B1"].
pub(super) fn pin_text(v: &PinValue) -> String {
    match v {
        PinValue::One(p) => format!("\"{}\"", clip(p)),
        PinValue::Bus(ps) => format!(
            "[{}]",
            ps.iter()
                .take(8)
                .map(|p| format!("\"{}\"", clip(p)))
                .collect::<Vec<_>>()
                .join(", ")
                + if ps.len() > 8 { ", ..." } else { "" }
        ),
    }
}

/// Finds `key` in `[table]` (`""`: top level; a dotted path such as `capacitive.coef` for a
/// nested or inline table) of the TOML text, in any layout (table headers, dotted keys,
/// inline tables, quoted names), and returns "line:column: " of the key or "".
pub fn locate(text: &str, table: &str, key: &str) -> String {
    let Ok(doc) = toml::de::DeTable::parse(text) else {
        return String::new();
    };
    let mut t = doc.get_ref();
    for part in table.split('.').filter(|p| !p.is_empty()) {
        match t.get(part).and_then(|v| v.get_ref().as_table()) {
            Some(inner) => t = inner,
            None => return String::new(),
        }
    }
    match t.get_key_value(key) {
        Some((k, _)) => {
            let (line, col) = line_col(text, k.span().start);
            format!("{line}:{col}: ")
        }
        None => String::new(),
    }
}

/// toml's message, plus the dotted key it concerns when the message does not name it.
pub(super) fn syntax_message(e: &toml::de::Error, text: &str) -> String {
    let message = e.message().trim().to_string();
    let keys = e.span().and_then(|s| key_path_at(text, s.start));
    match keys {
        Some(k) if !message.contains(&format!("`{k}`")) => format!("{message} (in `{k}`)"),
        Some(_) => message,
        None if message == "duplicate key" => match e.span().and_then(|s| text.get(s)) {
            Some(k) if !k.is_empty() => format!("duplicate key `{k}`"),
            _ => message,
        },
        None => message,
    }
}

/// The dotted key path of the value at byte offset `pos`, from the spans of toml's document
/// tree: a position inside a value (or on a table's header) names its key; a position on a
/// key (an unknown field) names the table holding it. `None` when the text does not parse
/// as TOML or `pos` lies outside every key and value.
fn key_path_at(text: &str, pos: usize) -> Option<String> {
    fn find(table: &toml::de::DeTable<'_>, pos: usize, path: &mut Vec<String>) -> bool {
        for (k, v) in table.iter() {
            if k.span().contains(&pos) {
                return true;
            }
            path.push(k.get_ref().to_string());
            // A `[table]`'s span is its header; its keys lie outside it, so look inside too.
            let inside = v.span().contains(&pos)
                || v.get_ref().as_table().is_some_and(|t| find(t, pos, path));
            if inside {
                return true;
            }
            path.pop();
        }
        false
    }
    let doc = toml::de::DeTable::parse(text).ok()?;
    let mut path = Vec::new();
    (find(doc.get_ref(), pos, &mut path) && !path.is_empty()).then(|| path.join("."))
}

/// 1-based line and column of byte offset `pos` in `text`.
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
    (line, col)
}
