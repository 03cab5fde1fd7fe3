//! `raytrace merge TILES... -o full.png`: placeholder.
