"""Picture plumbing shared by every check's pictures (matplotlib only below here)."""
