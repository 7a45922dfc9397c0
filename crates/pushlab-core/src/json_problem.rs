//! A JSON file's error as pushlab words it: where (line and column) and what, once for every JSON
//! file it reads (labels, setting, model, simulator spec, suite spec, bag choice), so that they all
//! read alike: `PATH: line 3, column 17: invalid type: string "big", expected f64`, or, when the
//! field is known, the field first, since in a one-line file the column says little:
//! `PATH: combined.horizon: invalid type: … (line 1, column 525)`.

use std::fmt;

/// Where a JSON document went wrong, and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct JsonProblem {
    /// 1-based; 0 when the error has no position (an I/O error while reading).
    pub line: usize,
    pub column: usize,
    /// The JSON path of the field that did not fit (`combined.horizon`), when known.
    pub field: Option<String>,
    /// serde_json's message, without the position it appends (this type names it first).
    pub message: String,
}

impl JsonProblem {
    /// The problem of a serde_json error.
    pub fn of(error: &serde_json::Error) -> Self {
        let text = error.to_string();
        let message = text
            .split(" at line ")
            .next()
            .unwrap_or_default()
            .to_owned();
        Self {
            line: error.line(),
            column: error.column(),
            field: None,
            message,
        }
    }

    /// The problem of a serde_json error at a field, named by its JSON path (`combined.horizon`), as
    /// `serde_path_to_error` gives it (`.` for the document itself).
    pub fn at_field(field: &str, error: &serde_json::Error) -> Self {
        let mut problem = Self::of(error);
        if field != "." && !field.is_empty() {
            problem.field = Some(field.to_owned());
        }
        problem
    }
}

/// Deserialises a JSON file's bytes: a value that does not fit is named by its field's JSON path
/// (`experiments[0]`, `combined.horizon`) as well as its line and column; trailing characters
/// after the value are an error, as in `serde_json::from_slice`. Every reader of a file a person
/// may edit by hand (model, setting, suite spec, simulator spec) reads through this.
pub fn from_file_bytes<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Result<T, JsonProblem> {
    let mut deserializer = serde_json::Deserializer::from_slice(bytes);
    let value = serde_path_to_error::deserialize(&mut deserializer)
        .map_err(|e| JsonProblem::at_field(&e.path().to_string(), e.inner()))?;
    deserializer.end().map_err(|e| JsonProblem::of(&e))?;
    Ok(value)
}

/// Deserialises JSON that a program built rather than a person typed (the Python package turns its
/// dicts into JSON): a value that does not fit is named by its field's path, without the line and
/// column of a text nobody saw (`kind: unknown variant `blob`, expected `range` or `event``).
pub fn from_built<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, JsonProblem> {
    from_file_bytes(text.as_bytes()).map_err(|problem| JsonProblem {
        line: 0,
        column: 0,
        ..problem
    })
}

impl fmt::Display for JsonProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.field, self.line) {
            (None, 0) => f.write_str(&self.message),
            (None, line) => write!(f, "line {line}, column {}: {}", self.column, self.message),
            (Some(field), 0) => write!(f, "{field}: {}", self.message),
            (Some(field), line) => write!(
                f,
                "{field}: {} (line {line}, column {})",
                self.message, self.column
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_names_the_field_and_the_position() {
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct Item {
            name: String,
        }
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct File {
            items: Vec<Item>,
        }
        let missing = from_file_bytes::<File>(b"{\"items\": [{\"name\": \"a\"},\n {}]}")
            .expect_err("no name");
        assert_eq!(
            missing.to_string(),
            "items[1]: missing field `name` (line 2, column 3)"
        );
        let trailing = from_file_bytes::<File>(b"{\"items\": []} x").expect_err("trailing");
        assert_eq!(
            trailing.to_string(),
            "line 1, column 15: trailing characters"
        );
    }

    #[test]
    fn built_json_names_the_field_not_a_position() {
        #[derive(Debug, serde::Deserialize)]
        #[allow(dead_code)]
        struct Spec {
            name: String,
            size: f64,
        }
        let wrong = from_built::<Spec>(r#"{"name": "a", "size": "big"}"#).expect_err("a string");
        assert_eq!(
            wrong.to_string(),
            "size: invalid type: string \"big\", expected f64"
        );
        let missing = from_built::<Spec>(r#"{"size": 1.0}"#).expect_err("no name");
        assert_eq!(missing.to_string(), "missing field `name`");
    }

    #[test]
    fn the_position_is_named_once_before_the_message() {
        let Err(e) = serde_json::from_str::<f64>("\n  \"big\"") else {
            panic!("a string is not a number");
        };
        let problem = JsonProblem::of(&e);
        assert_eq!((problem.line, problem.column), (2, 7));
        assert_eq!(
            problem.to_string(),
            "line 2, column 7: invalid type: string \"big\", expected f64"
        );
        assert_eq!(
            JsonProblem::at_field("a.b", &e).to_string(),
            "a.b: invalid type: string \"big\", expected f64 (line 2, column 7)"
        );
    }
}
