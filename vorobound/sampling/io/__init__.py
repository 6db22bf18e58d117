"""Files users bring and get: triangle meshes and sizing CSVs, ball files, L estimates."""
