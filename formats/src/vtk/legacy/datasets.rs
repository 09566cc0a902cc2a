//! Structured and polygonal legacy datasets.
