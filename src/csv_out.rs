//! CSV text written with the `csv` crate: a header row, then one record per row, `\n` line
//! ends, and RFC 4180 quoting only where a cell needs it (a comma, a quote or a line break),
//! so cells without those come out exactly as written.

use std::fmt::{Display, Write as _};

/// A CSV document being written into memory.
pub struct CsvText {
    w: csv::Writer<Vec<u8>>,
    cell: String,
}

impl CsvText {
    /// A document whose first row is `header`.
    pub fn new<H: AsRef<[u8]>>(header: impl IntoIterator<Item = H>) -> CsvText {
        let mut t = CsvText {
            w: csv::WriterBuilder::new().from_writer(Vec::new()),
            cell: String::new(),
        };
        t.record(header);
        t
    }

    /// Appends one row of ready-made cells.
    pub fn record<C: AsRef<[u8]>>(&mut self, cells: impl IntoIterator<Item = C>) {
        self.w.write_record(cells).expect(IN_MEMORY);
    }

    /// Appends one row, each cell as its `Display` text (formatted through one reused
    /// buffer, so a long simulation's rows allocate nothing).
    pub fn row(&mut self, cells: &[&dyn Display]) {
        for c in cells {
            self.cell.clear();
            let _ = write!(self.cell, "{c}");
            self.w.write_field(&self.cell).expect(IN_MEMORY);
        }
        self.w.write_record(None::<&[u8]>).expect(IN_MEMORY);
    }

    /// The finished text.
    pub fn finish(self) -> String {
        let bytes = self
            .w
            .into_inner()
            .map_err(|e| e.into_error())
            .expect(IN_MEMORY);
        // Every cell came from a `str`, so the bytes are UTF-8.
        String::from_utf8(bytes).expect("CSV cells are UTF-8 text")
    }
}

/// Why the writer's results are not errors: it writes into a `Vec<u8>`, which never fails,
/// and the header fixes the column count, which every caller's rows share (a row of another
/// length is a bug in sinedec, reported by csv as it happens).
const IN_MEMORY: &str = "writing CSV into memory with the header's column count cannot fail";
