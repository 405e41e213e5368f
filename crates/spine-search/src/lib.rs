//! # spine-search: gradient-free optimisers
