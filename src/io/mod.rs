//! Point-cloud input: LAS/LAZ and PLY readers, streamed in chunks.
