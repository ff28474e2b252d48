//! The resolver of [`read_usd_bytes`](super::read_usd_bytes): one USD file held in memory.

use std::io::{Cursor, Read, Seek, SeekFrom};
use std::sync::Arc;

/// Serves one USD file from memory and nothing else (for [`read_usd_bytes`](super::read_usd_bytes)). openusd opens the
/// root layer twice (once for its expression variables); every opening shares the one copy.
pub(super) struct MemoryResolver {
    name: String,
    bytes: Arc<[u8]>,
}

impl MemoryResolver {
    /// Serve `bytes` (copied once) under `name`.
    pub(super) fn new(name: &str, bytes: &[u8]) -> Self {
        MemoryResolver {
            name: name.to_string(),
            bytes: Arc::from(bytes),
        }
    }
}

/// One opening of [`MemoryResolver`]'s file.
struct MemoryAsset(Cursor<Arc<[u8]>>);

impl Read for MemoryAsset {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        self.0.read(buf)
    }
}

impl Seek for MemoryAsset {
    fn seek(&mut self, pos: SeekFrom) -> std::io::Result<u64> {
        self.0.seek(pos)
    }
}

impl openusd::ar::Asset for MemoryAsset {
    fn size(&self) -> std::io::Result<u64> {
        Ok(self.0.get_ref().len() as u64)
    }

    /// The bytes from the read position on, copied once.
    fn read_all(&mut self) -> std::io::Result<Vec<u8>> {
        let bytes = self.0.get_ref();
        let at = usize::try_from(self.0.position()).map_or(bytes.len(), |a| a.min(bytes.len()));
        let rest = bytes[at..].to_vec();
        self.0.set_position(bytes.len() as u64);
        Ok(rest)
    }
}

impl openusd::ar::Resolver for MemoryResolver {
    fn create_identifier(
        &self,
        asset_path: &str,
        _anchor: Option<&openusd::ar::ResolvedPath>,
    ) -> String {
        asset_path.to_string()
    }
    fn resolve(&self, asset_path: &str) -> Option<openusd::ar::ResolvedPath> {
        (asset_path == self.name).then(|| openusd::ar::ResolvedPath::new(&self.name))
    }
    fn resolve_for_new_asset(&self, _asset_path: &str) -> Option<openusd::ar::ResolvedPath> {
        None
    }
    fn open_asset(
        &self,
        resolved: &openusd::ar::ResolvedPath,
    ) -> std::io::Result<Box<dyn openusd::ar::Asset>> {
        if resolved.to_str() == Some(self.name.as_str()) {
            Ok(Box::new(MemoryAsset(Cursor::new(Arc::clone(&self.bytes)))))
        } else {
            Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                "only the file itself is available",
            ))
        }
    }
    fn get_modification_timestamp(
        &self,
        _asset_path: &str,
        _resolved: &openusd::ar::ResolvedPath,
    ) -> Option<std::time::SystemTime> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use openusd::ar::Resolver;

    #[test]
    fn every_opening_reads_the_same_bytes_from_its_position() {
        let r = MemoryResolver::new("memory.usdc", b"PXR-USDC and more");
        let resolved = r.resolve("memory.usdc").unwrap();
        assert!(r.resolve("other.usdc").is_none());
        for _ in 0..2 {
            let mut a = r.open_asset(&resolved).unwrap();
            assert_eq!(a.size().unwrap(), 17);
            assert_eq!(a.read_all().unwrap(), b"PXR-USDC and more");
            assert!(a.read_all().unwrap().is_empty());
        }
        let mut a = r.open_asset(&resolved).unwrap();
        a.seek(SeekFrom::Start(9)).unwrap();
        assert_eq!(a.read_all().unwrap(), b"and more");
        a.seek(SeekFrom::Start(100)).unwrap();
        assert!(a.read_all().unwrap().is_empty());
    }
}
