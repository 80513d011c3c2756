"""Built-in study files (TOML): the seed chapter's scenarios; see planar_sym.study."""
