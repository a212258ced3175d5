//! Source text → syntax tree with spans. pest stops at the first syntax error,
//! so a file yields one syntax diagnostic at most.

pub mod ast;
pub mod parser;
mod pest_error;
pub mod trivia;

use crate::diagnostic::Diagnostic;
use crate::span::FileId;
use parser::{AxleParser, Builder, Rule};
use pest::Parser;

/// Parses one file.
pub fn parse(file: FileId, text: &str) -> Result<ast::File, Diagnostic> {
    // Token-level detail makes errors name the missing `,` instead of a rule.
    pest::set_error_detail(true);
    match AxleParser::parse(Rule::file, text) {
        Ok(mut pairs) => {
            let root = pairs.next().expect("invariant: `file` matched");
            Ok(Builder { file }.file(root))
        }
        Err(e) => Err(pest_error::to_diagnostic(file, text, &e)),
    }
}
