//! Where a message points in the TOML text (line and column of a key, the dotted key at an
//! offset) and how a user's value is echoed in it.

/// `s` cut to 40 characters for echoing in a message.
pub fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}...", s.chars().take(40).collect::<String>())
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

/// [`locate`], or, for a key the text does not hold (a default), the position of the
/// nearest enclosing table's name (`[board]` for `board.iostandard`), so that every message
/// has a line and column; "" only when no part of the path is in the text.
pub fn locate_or_table(text: &str, table: &str, key: &str) -> String {
    let here = locate(text, table, key);
    if !here.is_empty() || table.is_empty() {
        return here;
    }
    let (parent, name) = table.rsplit_once('.').unwrap_or(("", table));
    locate_or_table(text, parent, name)
}

/// `message` with the position of every other key it names in backquotes (`` `adc.width` ``
/// becomes `` `adc.width` (12:1) ``) when the text holds it, so that every key taking part in
/// an error can be found; `blamed` (the error's own key, whose position leads the message)
/// and a name followed by " (" already are left as they are.
pub fn cite_keys(text: &str, message: &str, blamed: &str) -> String {
    let mut out = String::new();
    let mut rest = message;
    while let Some(i) = rest.find('`') {
        let Some(j) = rest[i + 1..].find('`') else {
            break;
        };
        let name = &rest[i + 1..i + 1 + j];
        out.push_str(&rest[..i + 2 + j]);
        rest = &rest[i + 2 + j..];
        let is_key = name.contains('.')
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '.');
        if is_key && name != blamed && !rest.starts_with(" (") {
            let (table, key) = name.rsplit_once('.').unwrap_or(("", name));
            let at = locate(text, table, key);
            if !at.is_empty() {
                out.push_str(&format!(" ({})", at.trim_end_matches(": ")));
            }
        }
    }
    out.push_str(rest);
    out
}

/// Whether the text holds `key` in `[table]` (the user wrote it; otherwise it is a default).
pub fn written(text: &str, table: &str, key: &str) -> bool {
    !locate(text, table, key).is_empty()
}

/// `s` with every control character (ESC, BEL, a newline, ...) escaped as in a Rust string
/// literal (`\u{1b}`), so that text from the config cannot drive the terminal.
pub fn escape_controls(s: &str) -> String {
    if !s.chars().any(char::is_control) {
        return s.to_string();
    }
    s.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_debug().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// serde's words for the expected type, in plain words: `expected u32` -> `expected a whole
/// number (0 or more)`, `map` -> `a table`, the pin value's untagged enum -> what a pin value
/// looks like.
fn plain_words(message: &str) -> String {
    let mut m = message.replace(
        "data did not match any variant of untagged enum PinValue",
        "expected a pin name such as \"E12\" or a list of them",
    );
    for (rust, plain) in [
        (" as i128", ""),
        (" as u128", ""),
        ("invalid type: map", "invalid type: a table"),
        ("invalid type: sequence", "invalid type: a list"),
        ("expected a sequence", "expected a list"),
        ("expected a boolean", "expected true or false"),
        (
            "expected enum Target",
            "expected \"spartan3an\" or \"cyclone3\"",
        ),
        (
            "expected enum AdcPreset",
            "expected \"ltc1407a-1\" or \"generic\"",
        ),
        (
            "expected enum Architecture",
            "expected \"unrolled\" or \"iterative\"",
        ),
        (
            "expected enum Method",
            "expected \"tracking\", \"kalman\", \"lsq\" or \"diff_lpf\"",
        ),
        (
            "expected enum FilterKind",
            "expected \"lowpass\", \"highpass\" or \"bandpass\"",
        ),
    ] {
        m = m.replace(rust, plain);
    }
    // Number types and struct / enum names after "expected ".
    let word_len = |s: &str| {
        s.find(|c: char| !(c.is_alphanumeric() || c == '_'))
            .unwrap_or(s.len())
    };
    let mut out = String::new();
    let mut rest = m.as_str();
    while let Some(i) = rest.find("expected ") {
        let (head, tail) = rest.split_at(i + "expected ".len());
        out.push_str(head);
        let w = &tail[..word_len(tail)];
        let (plain, used) = match w {
            "u8" | "u16" | "u32" | "u64" | "usize" => ("a whole number (0 or more)", w.len()),
            "i8" | "i16" | "i32" | "i64" | "isize" => ("a whole number", w.len()),
            "f32" | "f64" => ("a number", w.len()),
            "struct" | "enum" => {
                let after = &tail[w.len()..];
                let name = after
                    .strip_prefix(' ')
                    .map(|a| 1 + word_len(a))
                    .unwrap_or(0);
                let plain = if w == "struct" {
                    "a table"
                } else {
                    "one of the names the README lists for this key"
                };
                (plain, w.len() + name)
            }
            _ => ("", 0),
        };
        out.push_str(plain);
        rest = &tail[used..];
    }
    out.push_str(rest);
    out
}

/// toml's message in plain words, plus the dotted key it concerns when the message does
/// not name it.
pub(super) fn syntax_message(e: &toml::de::Error, text: &str) -> String {
    let message = plain_words(e.message().trim());
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
