//! A connection whose writes give up when the client stops taking a reply
//! ([`crate::ServeOptions::write_timeout`]).
//!
//! hyper has read timeouts (its header read timeout) but none for writes: a client that
//! sends a request and then never reads the reply (its receive window full) held its
//! connection, its slot among [`crate::ServeOptions::max_connections`] and the unsent
//! part of the reply for good. Here a write (or flush, or shutdown) that makes no
//! progress for the limit fails with [`std::io::ErrorKind::TimedOut`], which ends the
//! connection. The clock runs only while a write waits on the client: a slow reader
//! that keeps taking bytes is never cut off, and neither is a reply that waits on its
//! solve (the FFD mode's progress stream) with nothing to write.

use std::future::Future;
use std::io;
use std::pin::Pin;
use std::task::{Context, Poll};
use std::time::Duration;
use tokio::io::{AsyncRead, AsyncWrite, ReadBuf};

/// `inner` with its writes bounded in time (see the module's documentation).
#[derive(Debug)]
pub(crate) struct WriteTimeout<S> {
    inner: S,
    limit: Duration,
    /// Running while a write waits on the client; dropped when one makes progress.
    stalled: Option<Pin<Box<tokio::time::Sleep>>>,
}

impl<S> WriteTimeout<S> {
    /// `inner`, whose writes fail after `limit` without progress.
    pub(crate) fn new(inner: S, limit: Duration) -> Self {
        Self {
            inner,
            limit,
            stalled: None,
        }
    }

    /// What a write that made progress (`Ready`) or none (`Pending`) returns: progress
    /// stops the clock; no progress starts it, or fails once it has run out.
    fn watch<T>(&mut self, cx: &mut Context<'_>, poll: Poll<io::Result<T>>) -> Poll<io::Result<T>> {
        if poll.is_ready() {
            self.stalled = None;
            return poll;
        }
        let limit = self.limit;
        let clock = self.stalled.get_or_insert_with(|| Box::pin(tokio::time::sleep(limit)));
        match clock.as_mut().poll(cx) {
            Poll::Ready(()) => Poll::Ready(Err(io::Error::new(
                io::ErrorKind::TimedOut,
                format!(
                    "the client took none of the reply for {} s",
                    sheetform::geometry::short_number(limit.as_secs_f64())
                ),
            ))),
            Poll::Pending => Poll::Pending,
        }
    }
}

impl<S: AsyncRead + Unpin> AsyncRead for WriteTimeout<S> {
    fn poll_read(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &mut ReadBuf<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.get_mut().inner).poll_read(cx, buf)
    }
}

impl<S: AsyncWrite + Unpin> AsyncWrite for WriteTimeout<S> {
    fn poll_write(self: Pin<&mut Self>, cx: &mut Context<'_>, buf: &[u8]) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.inner).poll_write(cx, buf);
        this.watch(cx, poll)
    }

    fn poll_write_vectored(
        self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        bufs: &[io::IoSlice<'_>],
    ) -> Poll<io::Result<usize>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.inner).poll_write_vectored(cx, bufs);
        this.watch(cx, poll)
    }

    fn is_write_vectored(&self) -> bool {
        self.inner.is_write_vectored()
    }

    fn poll_flush(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.inner).poll_flush(cx);
        this.watch(cx, poll)
    }

    fn poll_shutdown(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        let this = self.get_mut();
        let poll = Pin::new(&mut this.inner).poll_shutdown(cx);
        this.watch(cx, poll)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio::io::AsyncWriteExt;

    /// A write the other end never reads fails after the limit; one it reads, however
    /// slowly, never does (the clock restarts with each byte taken).
    #[tokio::test(start_paused = true)]
    async fn a_write_fails_only_after_the_limit_without_progress() {
        let limit = Duration::from_secs(5);
        let (near, mut far) = tokio::io::duplex(16);
        let mut bounded = WriteTimeout::new(near, limit);
        // Read a byte every 4 s: slower than the write, but never 5 s without progress.
        let reader = tokio::spawn(async move {
            let mut taken = Vec::new();
            let mut byte = [0u8; 1];
            for _ in 0..40 {
                tokio::time::sleep(Duration::from_secs(4)).await;
                tokio::io::AsyncReadExt::read_exact(&mut far, &mut byte).await.unwrap();
                taken.push(byte[0]);
            }
            far
        });
        bounded.write_all(&[7u8; 56]).await.unwrap();
        let far = reader.await.unwrap();
        // Now nobody reads: the buffer (16 bytes) fills and the write waits, then fails.
        let start = tokio::time::Instant::now();
        let error = bounded.write_all(&[7u8; 64]).await.unwrap_err();
        assert_eq!(error.kind(), io::ErrorKind::TimedOut, "{error}");
        assert_eq!(start.elapsed(), limit);
        assert!(error.to_string().contains("for 5 s"), "{error}");
        drop(far);
    }
}
