//! Span measurement and dimension over balls (in progress).
