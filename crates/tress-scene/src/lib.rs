//! Scene files for tress: camera, lights, hair assets, head mesh and technique settings.
