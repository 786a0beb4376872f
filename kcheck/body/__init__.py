"""The body: reading meshes, mass properties, elastic materials."""
