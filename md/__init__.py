"""md: a compact molecular-dynamics engine for cemented grain packs (in development)."""
