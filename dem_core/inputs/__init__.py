"""What a run is given: scenes and their builders, scene files, ground motions and records."""
