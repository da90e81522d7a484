"""Library modules that asmcheck provides itself (TimeLibrary is written in AsmetaL)."""
