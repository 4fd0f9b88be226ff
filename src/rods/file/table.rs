//! Rods from a CSV table: a header naming the columns of [`FIELDS`] in any
//! order (and `id`, if the rods are numbered), other columns ignored, `#`
//! comment lines anywhere, each row named by its line in the file.

use super::format::{FIELDS, Raw, id_of, number, rod_of};
use crate::{Error, Result};

/// The rods of a CSV table, in the file's frame.
pub(super) fn parse_csv(text: &str, bad: &impl Fn(usize, String) -> Error) -> Result<Vec<Raw>> {
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader.headers().map_err(|e| bad(1, e.to_string()))?.clone();
    if let Some(twice) = FIELDS
        .iter()
        .chain(&["id"])
        .find(|f| header.iter().filter(|h| h == *f).count() > 1)
    {
        return Err(bad(
            1,
            format!("the header names the column {twice:?} twice"),
        ));
    }
    let at: Vec<usize> = FIELDS
        .iter()
        .map(|f| {
            header.iter().position(|h| h == *f).ok_or_else(|| {
                bad(
                    1,
                    format!(
                        "the header has no column {f:?} (it needs {})",
                        FIELDS.join(",")
                    ),
                )
            })
        })
        .collect::<Result<_>>()?;
    let id = header.iter().position(|h| h == "id");
    let mut raws = Vec::new();
    let mut record = csv::StringRecord::new();
    // The csv crate's own line count skips comment lines and counts CRLF
    // line ends twice, so lines are counted here, from each record's offset.
    let mut lines = LineCounter::new(text);
    loop {
        let line = lines.at(reader.position().byte() as usize);
        match reader.read_record(&mut record) {
            Ok(false) => break,
            Ok(true) => {}
            Err(e) => return Err(bad(line, e.to_string())),
        }
        let line = record
            .position()
            .map_or(line, |p| lines.record(p.byte() as usize));
        if record.len() < header.len() {
            return Err(bad(
                line,
                format!("{} of {} fields", record.len(), header.len()),
            ));
        }
        if record.len() > header.len() {
            return Err(bad(
                line,
                format!(
                    "{} fields, but the header names {}",
                    record.len(),
                    header.len()
                ),
            ));
        }
        let mut v = [0.0; 8];
        for (k, &col) in at.iter().enumerate() {
            v[k] = number(&record[col], FIELDS[k]).map_err(|why| bad(line, why))?;
        }
        let id = id
            .map(|col| id_of(&record[col]))
            .transpose()
            .map_err(|why| bad(line, why))?;
        raws.push(Raw {
            line,
            rod: rod_of(v),
            id,
        });
    }
    Ok(raws)
}

/// Line numbers of byte offsets met in increasing order, with `\n`, `\r\n`
/// and a lone `\r` each ending a line.
struct LineCounter<'a> {
    text: &'a [u8],
    offset: usize,
    line: usize,
}

impl<'a> LineCounter<'a> {
    fn new(text: &'a str) -> Self {
        LineCounter {
            text: text.as_bytes(),
            offset: 0,
            line: 1,
        }
    }

    /// The line holding byte `offset` (not before the last one asked).
    fn at(&mut self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        while self.offset < end {
            let b = self.text[self.offset];
            let next = self.text.get(self.offset + 1);
            if b == b'\n' || (b == b'\r' && next != Some(&b'\n')) {
                self.line += 1;
            }
            self.offset += 1;
        }
        self.line
    }

    /// The line of the record the csv crate places at `offset`: where it
    /// started reading, before the line breaks and comment lines it skipped.
    fn record(&mut self, offset: usize) -> usize {
        let mut at = offset;
        self.at(at);
        while let Some(&b) = self.text.get(at) {
            match b {
                b'\n' | b'\r' => at += 1,
                b'#' => {
                    while self.text.get(at).is_some_and(|&c| c != b'\n' && c != b'\r') {
                        at += 1;
                    }
                }
                _ => break,
            }
            self.at(at);
        }
        self.line
    }
}
