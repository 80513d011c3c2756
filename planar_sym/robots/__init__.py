"""Built-in robot descriptions (TOML), written from the seed chapter's tables."""
