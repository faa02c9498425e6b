"""burial: burial paths, quartz cementation, compaction and clay diagenesis (in development)."""
