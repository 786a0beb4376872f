"""Pictures of the built-in checks; imported only when pictures are asked for."""
