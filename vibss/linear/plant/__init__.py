"""The plant: assembly of M, C, K, signal names, build_plant, the Plant and its terms."""
