"""What measures: CPU time and peak memory (``usage``), allocations (``alloccount`` and its C
extension), rays (``raycount``), image error and heat maps (``imagediff``), POV-Ray as a
measuring stick (``povray``)."""
