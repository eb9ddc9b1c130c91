//! pbrt-v4's tokens: bare words (directive names, numbers, `true` and `false`), quoted
//! strings (with `\"`, `\\`, `\n` and `\t` escapes), `[` and `]`, and comments from `#` to
//! the end of the line, each token with the line it starts on.

use super::super::SceneError;
use std::path::Path;

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub enum Tok {
    /// A word outside quotes: a directive, a number, `true` or `false`.
    Word(String),
    /// A quoted string, unescaped.
    Str(String),
    /// `[`
    Open,
    /// `]`
    Close,
}

/// A token and the line (1-based) it starts on.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub tok: Tok,
    pub line: usize,
}

impl Token {
    /// The token as the file has it, for messages.
    pub fn describe(&self) -> String {
        match &self.tok {
            Tok::Word(w) => format!("`{w}`"),
            Tok::Str(s) => format!("\"{s}\""),
            Tok::Open => "`[`".into(),
            Tok::Close => "`]`".into(),
        }
    }
}

/// Splits `text`, read from `file`, into tokens.
pub fn tokenize(text: &str, file: &Path) -> Result<Vec<Token>, SceneError> {
    let mut tokens = Vec::new();
    let mut line = 1;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\n' => line += 1,
            c if c.is_whitespace() => {}
            '#' => {
                while chars.peek().is_some_and(|&c| c != '\n') {
                    chars.next();
                }
            }
            '[' => tokens.push(Token { tok: Tok::Open, line }),
            ']' => tokens.push(Token { tok: Tok::Close, line }),
            '"' => {
                let start = line;
                let mut s = String::new();
                loop {
                    match chars.next() {
                        None => return Err(SceneError::new(file, Some(start), None, "a quoted string is not closed")),
                        Some('"') => break,
                        Some('\n') => return Err(SceneError::new(file, Some(start), None, "a new line inside a quoted string")),
                        Some('\\') => match chars.next() {
                            Some('n') => s.push('\n'),
                            Some('t') => s.push('\t'),
                            Some('b') => s.push('\u{8}'),
                            Some('f') => s.push('\u{c}'),
                            Some('r') => s.push('\r'),
                            Some(c @ ('"' | '\\' | '\'')) => s.push(c),
                            other => {
                                let what = other.map_or("the end of the file".to_owned(), |c| format!("`{c}`"));
                                return Err(SceneError::new(
                                    file,
                                    Some(line),
                                    None,
                                    format!("unexpected escape \\ before {what} in a quoted string"),
                                ));
                            }
                        },
                        Some(c) => s.push(c),
                    }
                }
                tokens.push(Token { tok: Tok::Str(s), line: start });
            }
            c => {
                let mut w = String::from(c);
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#') {
                        break;
                    }
                    w.push(c);
                    chars.next();
                }
                tokens.push(Token { tok: Tok::Word(w), line });
            }
        }
    }
    Ok(tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_strings_brackets_and_lines() {
        let t = tokenize("Shape \"sphere\" # comment\n \"float radius\" [2.5]\n\"a\\\"b\"", Path::new("x.pbrt")).unwrap();
        let toks: Vec<_> = t.iter().map(|t| (t.tok.clone(), t.line)).collect();
        assert_eq!(
            toks,
            vec![
                (Tok::Word("Shape".into()), 1),
                (Tok::Str("sphere".into()), 1),
                (Tok::Str("float radius".into()), 2),
                (Tok::Open, 2),
                (Tok::Word("2.5".into()), 2),
                (Tok::Close, 2),
                (Tok::Str("a\"b".into()), 3),
            ]
        );
        assert!(tokenize("\"open", Path::new("x.pbrt")).is_err());
    }
}
