//! The mutations: byte-level and line-level, with the numbers, tokens, paths and signatures they insert.

use super::*;

/// Numbers that loaders get wrong: not finite, at the edges of integer and float types, zero,
/// negative, written oddly.
pub(crate) const NUMBERS: &[&str] = &[
    "NaN",
    "nan",
    "inf",
    "-inf",
    "+inf",
    "-1",
    "0",
    "-0",
    "1",
    "2",
    "65",
    "257",
    "16384",
    "16385",
    "60000",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "9223372036854775807",
    "9223372036854775808",
    "-9223372036854775809",
    "18446744073709551616",
    "99999999999999999999999",
    "1e-45",
    "1e-320",
    "3.4028235e38",
    "3.5e38",
    "1e39",
    "-1e39",
    "1e308",
    "1e309",
    "0.0000001",
    "1.",
    "-.5",
    "0x10",
    "1_000",
    "00012",
    "1e",
];

/// Tokens for text files: TOML, OBJ and MTL syntax out of place, odd characters.
pub(crate) const TOKENS: &[&str] = &[
    "\"\"",
    "\"",
    "'",
    "'''",
    "\"\"\"",
    "[]",
    "[",
    "]",
    "[[",
    "]]",
    "{}",
    "{",
    "=",
    "==",
    ",",
    ".",
    "#",
    "\\",
    "\\u0000",
    "\\uD800",
    "/",
    "//",
    "///",
    "\t",
    "\r",
    "\r\n",
    "\n\n",
    "\0",
    "é",
    "\u{feff}",
    "\u{202e}",
    "\u{1f4a5}",
    "[camera]",
    "[render]",
    "[[meshes]]",
    "[[materials]]",
    "[[lights]]",
    "description = \"again\"",
    "type = \"polygon\"",
    "type = \"ggx\"",
    "vertices = []",
    "vertices = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]",
    "scale = [0, 0, 0]",
    "scale = []",
    "two_sided = 1",
    "uv_projection = \"spherical\"",
    "obj = \"\"",
    "kd_map = \"textures\"",
    "v",
    "vt",
    "vn",
    "f",
    "f 1 2 3",
    "f -1 -2 -3",
    "f 1/1/1 2/2/2 3/3/3",
    "f 1//1 2//1 3//1",
    "f 1/1 2/2 3/3 4/4 5/5 6/6",
    "f 0 0 0",
    "f 2147483648 1 2",
    "f -2147483649 1 2",
    "f 1 2",
    "f 1/2/3/4 2 3",
    "f 1/ 2/ 3/",
    "v 1e39 0 0",
    "v 0 0 0 0",
    "v 1 1 1 1e-45",
    "v 0 0 0 1 0 0",
    "vt nan nan",
    "vt 1e39 0",
    "vn 0 0 0",
    "o",
    "g",
    "s off",
    "l 1 2",
    "p 1",
    "usemtl",
    "usemtl nosuch",
    "mtllib",
    "mtllib model.mtl",
    "mtllib model.mtl model.mtl",
    "mtllib textures",
    "newmtl",
    "newmtl clay",
    "Kd",
    "Kd 1 1",
    "Ks 2 2 2",
    "Ns -5",
    "Ns 1e39",
    "Pr nan",
    "Pm 2",
    "d -1",
    "map_Kd",
    "map_Kd -bm",
    "map_Kd textures/albedo.png",
    "map_Kd textures",
    "map_Kd model.mtl",
];

/// Strings put in place of a quoted string or a file name: empty, folders, missing files,
/// files of another kind, devices.
pub(crate) const PATHS: &[&str] = &[
    "",
    " ",
    ".",
    "..",
    "/",
    "textures",
    "textures/",
    "nosuch.obj",
    "nosuch.png",
    "model.mtl",
    "scene.toml",
    "model.obj",
    "a\\b.png",
    "/dev/null",
    "/dev/zero",
    "\u{0}",
    "name with spaces.obj",
];

/// Interesting 16- and 32-bit values for binary headers.
pub(crate) const WORDS: &[u32] = &[
    0,
    1,
    2,
    7,
    8,
    255,
    256,
    4096,
    16384,
    16385,
    32767,
    32768,
    60000,
    65535,
    65536,
    0x7fff_ffff,
    0xffff_ffff,
];

/// File signatures (one makes the texture loader see another format).
pub(crate) const MAGICS: &[&[u8]] = &[
    b"\x89PNG\r\n\x1a\n",
    b"\xff\xd8\xff",
    b"\xff\xd8\xff\xe0",
    b"v/1\x01",
    b"GIF89a",
    b"BM",
    b"RIFF\0\0\0\0WEBP",
    b"II*\0",
    b"#?RADIANCE\n",
    b"P6\n",
    b"qoif",
];

/// Applies one random byte-level mutation to `data`. `text` allows the large insertions (very
/// long lines) that only text formats can take without being cut short by a size check.
pub(crate) fn mutate_bytes(rng: &mut Rng, data: &mut Vec<u8>, corpus: &Corpus, text: bool, log: &mut String) {
    let position = |rng: &mut Rng, data: &Vec<u8>| rng.below(data.len() + 1);
    match rng.below(11) {
        0 if !data.is_empty() => {
            let i = rng.below(data.len());
            data[i] = rng.next_u64() as u8;
            let _ = write!(log, "set byte {i}; ");
        }
        1 if !data.is_empty() => {
            let i = rng.below(data.len());
            data[i] ^= 1 << rng.below(8);
            let _ = write!(log, "flip a bit of byte {i}; ");
        }
        2 => {
            let at = position(rng, data);
            data.truncate(at);
            let _ = write!(log, "truncate at {at}; ");
        }
        3 => {
            let at = position(rng, data);
            let token = if rng.one_in(2) { *rng.pick(NUMBERS) } else { *rng.pick(TOKENS) };
            data.splice(at..at, token.bytes());
            let _ = write!(log, "insert {token:?} at {at}; ");
        }
        4 if !data.is_empty() => {
            let at = rng.below(data.len());
            let most = if rng.one_in(4) { data.len() / 4 + 1 } else { 16 };
            let len = 1 + rng.below(most);
            let end = (at + len).min(data.len());
            data.drain(at..end);
            let _ = write!(log, "delete {at}..{end}; ");
        }
        5 if !data.is_empty() => {
            let from = rng.below(data.len());
            let end = (from + 1 + rng.below(256)).min(data.len());
            let chunk = data[from..end].to_vec();
            let at = position(rng, data);
            data.splice(at..at, chunk);
            let _ = write!(log, "copy {from}..{end} to {at}; ");
        }
        6 => {
            let junk: Vec<u8> = (0..1 + rng.below(64)).map(|_| rng.next_u64() as u8).collect();
            let at = position(rng, data);
            let _ = write!(log, "insert {} random bytes at {at}; ", junk.len());
            data.splice(at..at, junk);
        }
        7 => {
            let other = match rng.below(3) {
                0 => &rng.pick(&corpus.scenes).bytes,
                1 => &rng.pick(&corpus.models).bytes,
                _ => &rng.pick(&corpus.textures).bytes,
            };
            let from = rng.below(other.len());
            let end = (from + 1 + rng.below(512)).min(other.len());
            let at = position(rng, data);
            data.splice(at..at, other[from..end].iter().copied());
            let _ = write!(log, "splice {} bytes of another seed at {at}; ", end - from);
        }
        8 if text => {
            let unit = if rng.one_in(2) { *rng.pick(NUMBERS) } else { *rng.pick(TOKENS) };
            let unit = if unit.is_empty() { "9" } else { unit };
            let length = 1000 + rng.below(100_000);
            let long: String = unit.repeat(length / unit.len() + 1);
            let at = position(rng, data);
            let line = if rng.one_in(2) { format!("\n{long}\n") } else { long };
            let _ = write!(log, "insert a {}-byte run of {unit:?} at {at}; ", line.len());
            data.splice(at..at, line.into_bytes());
        }
        9 if data.len() >= 4 => {
            let i = rng.below(data.len() - 3);
            let word = *rng.pick(WORDS);
            let bytes = match rng.below(4) {
                0 => word.to_le_bytes().to_vec(),
                1 => word.to_be_bytes().to_vec(),
                2 => (word as u16).to_le_bytes().to_vec(),
                _ => (word as u16).to_be_bytes().to_vec(),
            };
            data[i..i + bytes.len()].copy_from_slice(&bytes);
            let _ = write!(log, "write {word} ({} bytes) at {i}; ", bytes.len());
        }
        _ => {
            let magic = *rng.pick(MAGICS);
            let at = if rng.one_in(2) { 0 } else { position(rng, data) };
            if rng.one_in(2) && data.len() >= at + magic.len() {
                data[at..at + magic.len()].copy_from_slice(magic);
                let _ =
                    write!(log, "overwrite with signature {:?} at {at}; ", magic.escape_ascii().to_string());
            } else {
                data.splice(at..at, magic.iter().copied());
                let _ = write!(log, "insert signature {:?} at {at}; ", magic.escape_ascii().to_string());
            }
        }
    }
}

/// Applies one line-level mutation to a text file.
pub(crate) fn mutate_lines(rng: &mut Rng, data: &mut Vec<u8>, corpus: &Corpus, log: &mut String) {
    let text = String::from_utf8_lossy(data).into_owned();
    let mut lines: Vec<String> = text.split('\n').map(str::to_string).collect();
    let n = lines.len();
    let i = rng.below(n);
    match rng.below(9) {
        0 => {
            lines.remove(i);
            let _ = write!(log, "delete line {}; ", i + 1);
        }
        1 => {
            let most = (100_000 / (lines[i].len() + 1)).max(1);
            let copies = if rng.one_in(8) { 1 + rng.below(2000).min(most) } else { 1 };
            for _ in 0..copies {
                lines.insert(i, lines[i].clone());
            }
            let _ = write!(log, "repeat line {} {copies} times; ", i + 1);
        }
        2 => {
            let j = rng.below(n);
            lines.swap(i, j);
            let _ = write!(log, "swap lines {} and {}; ", i + 1, j + 1);
        }
        3 => {
            let number = *rng.pick(NUMBERS);
            let replaced = replace_number(rng, &lines[i], number);
            let _ = write!(log, "line {}: a number to {number:?}; ", i + 1);
            lines[i] = replaced;
        }
        4 => {
            let line = rng.pick(&corpus.lines).clone();
            let _ = write!(log, "insert {line:?} before line {}; ", i + 1);
            lines.insert(i, line);
        }
        5 => {
            let token = *rng.pick(TOKENS);
            let _ = write!(log, "line {} becomes {token:?}; ", i + 1);
            lines[i] = token.to_string();
        }
        6 => {
            // A whole section (from a header or `newmtl`/`o` line to the next) again, at the end.
            let starts: Vec<usize> = (0..n)
                .filter(|&k| {
                    let l = lines[k].trim_start();
                    l.starts_with('[') || l.starts_with("newmtl") || l.starts_with("o ")
                })
                .collect();
            if let Some(&start) = starts.get(rng.below(starts.len().max(1))) {
                let end = starts.iter().copied().find(|&k| k > start).unwrap_or(n);
                let section: Vec<String> = lines[start..end].to_vec();
                let _ = write!(log, "repeat lines {}..{} at the end; ", start + 1, end);
                lines.extend(section);
            }
        }
        7 => {
            let path = *rng.pick(PATHS);
            let replaced = replace_name(&lines[i], path);
            let _ = write!(log, "line {}: a name to {path:?}; ", i + 1);
            lines[i] = replaced;
        }
        _ => {
            let j = rng.below(n);
            let line = lines.remove(i);
            lines.insert(j.min(lines.len()), line);
            let _ = write!(log, "move line {} to {}; ", i + 1, j + 1);
        }
    }
    *data = lines.join("\n").into_bytes();
}

/// `line` with one of its numbers (chosen by `rng`) replaced by `number`; the line as it is
/// when it has none.
pub(crate) fn replace_number(rng: &mut Rng, line: &str, number: &str) -> String {
    let bytes = line.as_bytes();
    let mut spans = Vec::new();
    let mut k = 0;
    while k < bytes.len() {
        let starts = bytes[k].is_ascii_digit()
            || (matches!(bytes[k], b'-' | b'+' | b'.') && bytes.get(k + 1).is_some_and(u8::is_ascii_digit));
        if starts && (k == 0 || !bytes[k - 1].is_ascii_alphanumeric()) {
            let begin = k;
            k += 1;
            while k < bytes.len()
                && (bytes[k].is_ascii_digit() || matches!(bytes[k], b'.' | b'e' | b'E' | b'-' | b'+'))
            {
                k += 1;
            }
            spans.push(begin..k);
        } else {
            k += 1;
        }
    }
    if spans.is_empty() {
        return line.to_string();
    }
    let span = spans[rng.below(spans.len())].clone();
    format!("{}{number}{}", &line[..span.start], &line[span.end..])
}

/// `line` with its quoted string (TOML) or last word (OBJ and MTL statements) replaced by `name`.
pub(crate) fn replace_name(line: &str, name: &str) -> String {
    if let (Some(open), Some(close)) = (line.find('"'), line.rfind('"')) {
        if close > open {
            return format!("{}\"{name}\"{}", &line[..open], &line[close + 1..]);
        }
    }
    match line.trim_end().rfind(char::is_whitespace) {
        Some(k) => format!("{} {name}", &line[..k]),
        None => format!("{line} {name}"),
    }
}

/// The IEEE CRC-32 of PNG chunks.
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xffff_ffffu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 { (crc >> 1) ^ 0xedb8_8320 } else { crc >> 1 };
        }
    }
    !crc
}

/// The chunks of a PNG file: (offset of the length field, data length), as far as they parse.
pub(crate) fn png_chunks(data: &[u8]) -> Vec<(usize, usize)> {
    let mut chunks = Vec::new();
    let mut at = 8;
    while at + 12 <= data.len() {
        let length = u32::from_be_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]) as usize;
        if at + 12 + length > data.len() {
            break;
        }
        chunks.push((at, length));
        at += 12 + length;
    }
    chunks
}

/// A mutation that knows the format's header, so that the file still passes its checksums or
/// reaches the size fields: PNG (a field of a chunk, CRC fixed), JPEG (the frame header's
/// size and components), TGA (the header's sizes, type, depth and colour map).
pub(crate) fn mutate_header(rng: &mut Rng, data: &mut [u8], name: &str, log: &mut String) {
    let word = *rng.pick(WORDS);
    if data.starts_with(b"\x89PNG") {
        let chunks = png_chunks(data);
        let Some(&(at, length)) = chunks.get(rng.below(chunks.len().max(1))) else { return };
        let kind = [data[at + 4], data[at + 5], data[at + 6], data[at + 7]];
        let field = match (&kind, rng.below(4)) {
            (b"IHDR", 0) if length >= 8 => {
                data[at + 8..at + 12].copy_from_slice(&word.to_be_bytes());
                format!("IHDR width {word}")
            }
            (b"IHDR", 1) if length >= 8 => {
                data[at + 12..at + 16].copy_from_slice(&word.to_be_bytes());
                format!("IHDR height {word}")
            }
            (b"IHDR", 2) if length >= 13 => {
                let offset = at + 16 + rng.below(5);
                let value = *rng.pick(&[0u8, 1, 2, 3, 4, 6, 7, 8, 16, 255]);
                data[offset] = value;
                format!("IHDR byte {} = {value}", offset - at - 8)
            }
            _ if length > 0 => {
                let offset = at + 8 + rng.below(length);
                data[offset] = rng.next_u64() as u8;
                format!("byte {} of chunk {}", offset - at - 8, String::from_utf8_lossy(&kind))
            }
            _ => return,
        };
        let crc = crc32(&data[at + 4..at + 8 + length]);
        data[at + 8 + length..at + 12 + length].copy_from_slice(&crc.to_be_bytes());
        let _ = write!(log, "PNG {field}, CRC fixed; ");
    } else if data.starts_with(b"\xff\xd8") {
        let Some(sof) = (2..data.len().saturating_sub(9))
            .find(|&k| data[k] == 0xff && matches!(data[k + 1], 0xc0..=0xc2))
        else {
            return;
        };
        let value = (word as u16).to_be_bytes();
        match rng.below(4) {
            0 => data[sof + 5..sof + 7].copy_from_slice(&value),
            1 => data[sof + 7..sof + 9].copy_from_slice(&value),
            2 => data[sof + 9] = *rng.pick(&[0u8, 1, 2, 3, 4, 255]),
            _ => {
                let k = (sof + 11).min(data.len() - 1);
                data[k] = rng.next_u64() as u8;
            }
        }
        let _ = write!(log, "JPEG frame header with {word}; ");
    } else if name.ends_with(".tga") && data.len() >= 18 {
        match rng.below(5) {
            0 => data[12..14].copy_from_slice(&(word as u16).to_le_bytes()),
            1 => data[14..16].copy_from_slice(&(word as u16).to_le_bytes()),
            2 => data[2] = *rng.pick(&[0u8, 1, 2, 3, 9, 10, 11, 32, 33, 255]),
            3 => data[16] = *rng.pick(&[0u8, 1, 8, 15, 16, 24, 32, 255]),
            _ => {
                let k = 1 + rng.below(7);
                data[k] = word as u8;
            }
        }
        let _ = write!(log, "TGA header with {word}; ");
    }
}
