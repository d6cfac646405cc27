//! The sprung engine.
