//! The live Foxglove view (feature `live`): the run served over the Foxglove WebSocket
//! protocol (subprotocol `foxglove.sdk.v1`) by the foxglove SDK's server, on the same
//! channels, schemas and protobuf messages as the MCAP file: the run's channels, and the
//! optional ones its options ask for (`/sensors/imu` and `/sensors/mocap`, `/wind`,
//! `/estimate`; [`crate::schema::declared_channels`]).
//!
//! The channels live in a context of their own (nothing else logs to them). A channel has a
//! sink only while a client subscribes to it, and a sample's message is encoded only for
//! such channels, so without a client the view costs a check per message.
//!
//! [`crate::Recorder::wait_for_live_client`] blocks until a client has subscribed to one of
//! the server's channels (`flapwing hover --foxglove --wait-for-client`): the server's
//! listener counts its clients' connections and subscriptions in a [`ClientWatch`].

use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use foxglove::websocket::{ChannelView, Client, ServerListener};
use foxglove::{
    Context, PartialMetadata, RawChannel, Schema, WebSocketServer, WebSocketServerHandle,
};

use crate::error::{Error, Result};
use crate::options::LogOptions;
use crate::sample::{Encoded, Sample};
use crate::schema::{self, MESSAGE_ENCODING, OPTIONAL_CHANNELS, SCHEMA_ENCODING, WingLayout};

/// The running server and its channels (in the order of [`schema::declared_channels`]).
pub(crate) struct LiveSink {
    server: WebSocketServerHandle,
    channels: Vec<Arc<RawChannel>>,
    /// Each of [`OPTIONAL_CHANNELS`]' index in `channels`, if declared.
    optional: [Option<usize>; OPTIONAL_CHANNELS.len()],
    /// The indexes of /events, /scene/wings and /scene/forces in `channels`.
    events: usize,
    scene_wings: usize,
    scene_forces: usize,
    buf: Vec<u8>,
    /// Whether the current /scene/wings subscription has had the planforms.
    scene_sent: bool,
    /// Keeps the channels' context alive.
    _context: Arc<Context>,
    /// The server's clients, as its listener counts them.
    watch: Arc<ClientWatch>,
}

/// Counts a server's client connections and current subscriptions (its listener).
#[derive(Debug, Default)]
struct ClientWatch {
    /// Clients that ever connected.
    connected: AtomicUsize,
    /// Channel subscriptions currently held, over all clients.
    subscriptions: AtomicUsize,
}

impl ServerListener for ClientWatch {
    fn on_client_connect(&self) {
        self.connected.fetch_add(1, Ordering::SeqCst);
    }

    // Called after the channel has its sink, so a message logged from now on reaches it.
    fn on_subscribe(&self, _client: Client, _channel: ChannelView) {
        self.subscriptions.fetch_add(1, Ordering::SeqCst);
    }

    fn on_unsubscribe(&self, _client: Client, _channel: ChannelView) {
        let _ = self
            .subscriptions
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| n.checked_sub(1));
    }
}

/// How [`crate::Recorder::wait_for_live_client`] ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LiveWait {
    /// A client has subscribed to at least one channel: messages logged now reach it.
    Subscribed,
    /// The timeout passed first; `connected` tells whether a client connected without
    /// subscribing.
    TimedOut {
        /// A client connected (but subscribed to nothing).
        connected: bool,
    },
    /// `cancel` returned true first (Ctrl-C).
    Cancelled,
    /// The recorder serves no live view.
    NoServer,
}

/// Blocks until a client of the server counted by `watch` subscribes to one of its
/// channels, `timeout` passes (`None`: no limit) or `cancel` returns true (checked every
/// 20 ms). Returns at once when a client already subscribes.
fn wait_for_client(
    watch: &ClientWatch,
    timeout: Option<Duration>,
    cancel: impl Fn() -> bool,
) -> LiveWait {
    let start = Instant::now();
    loop {
        if watch.subscriptions.load(Ordering::SeqCst) > 0 {
            return LiveWait::Subscribed;
        }
        if cancel() {
            return LiveWait::Cancelled;
        }
        if timeout.is_some_and(|t| start.elapsed() >= t) {
            return LiveWait::TimedOut {
                connected: watch.connected.load(Ordering::SeqCst) > 0,
            };
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `host:port` split (an IPv6 host in brackets: `[::1]:8765`).
fn host_port(addr: &str) -> Result<(String, u16)> {
    let bad = |why: &str| {
        Error::Options(format!(
            "--foxglove address `{addr}`: {why} (expected HOST:PORT, e.g. 127.0.0.1:8765)"
        ))
    };
    let (host, port) = addr.rsplit_once(':').ok_or_else(|| bad("no port"))?;
    let port = port
        .parse::<u16>()
        .map_err(|_| bad("the port is not a number 0-65535"))?;
    let host = host.trim_start_matches('[').trim_end_matches(']');
    if host.is_empty() {
        return Err(bad("no host"));
    }
    Ok((host.to_owned(), port))
}

impl LiveSink {
    /// Starts the server at `addr` (`host:port`; port 0 picks a free one) with the channels
    /// a log of a vehicle with `wings` and `options` declares.
    pub fn start(addr: &str, options: &LogOptions, wings: &WingLayout) -> Result<Self> {
        let (host, port) = host_port(addr)?;
        let context = Context::new();
        let declared = schema::declared_channels(wings, options);
        let mut optional = [None; OPTIONAL_CHANNELS.len()];
        for (i, c) in OPTIONAL_CHANNELS.iter().enumerate() {
            optional[i] = declared.iter().position(|d| d.0 == c.0);
        }
        let mut channels = Vec::with_capacity(declared.len());
        for (topic, name) in declared {
            let data = schema::schema_data(name).unwrap_or_default();
            let channel = context
                .channel_builder(topic.as_str())
                .message_encoding(MESSAGE_ENCODING)
                .schema(Schema::new(name, SCHEMA_ENCODING, data))
                .build_raw()
                .map_err(|e| Error::Options(format!("Foxglove channel {topic}: {e}")))?;
            channels.push(channel);
        }
        let watch = Arc::new(ClientWatch::default());
        let server = WebSocketServer::new()
            .name("flapwing")
            .bind(host, port)
            .context(&context)
            .listener(Arc::clone(&watch) as Arc<dyn ServerListener>)
            .start_blocking()
            .map_err(|e| {
                Error::Options(format!(
                    "cannot serve the live Foxglove view at `{addr}`: {e}"
                ))
            })?;
        Ok(Self {
            server,
            channels,
            optional,
            events: wings.events(),
            scene_wings: wings.scene_wings(),
            scene_forces: wings.scene_forces(),
            buf: Vec::new(),
            scene_sent: false,
            _context: context,
            watch,
        })
    }

    /// Blocks until a client subscribes (see [`crate::Recorder::wait_for_live_client`]).
    pub fn wait_for_client(
        &self,
        timeout: Option<Duration>,
        cancel: impl Fn() -> bool,
    ) -> LiveWait {
        wait_for_client(&self.watch, timeout, cancel)
    }

    /// The port the server listens on.
    pub fn port(&self) -> u16 {
        self.server.port()
    }

    /// True while a client subscribes to at least one channel.
    pub fn wanted(&self) -> bool {
        self.channels.iter().any(|c| c.has_sinks())
    }

    fn log(&mut self, index: usize, t_ns: u64, m: &dyn Encoded) {
        let channel = &self.channels[index];
        if channel.has_sinks() {
            self.buf.clear();
            m.put(&mut self.buf);
            channel.log_with_meta(
                &self.buf,
                PartialMetadata {
                    log_time: Some(t_ns),
                },
            );
        }
    }

    /// Sends a sample to the clients subscribed to its channels.
    pub fn sample(&mut self, s: &Sample) {
        s.each(|i, m| self.log(i, s.t_ns, m));
    }

    /// Sends a message on optional channel `opt` (an index into [`OPTIONAL_CHANNELS`]) if
    /// the run declared it.
    pub fn optional(&mut self, opt: usize, t_ns: u64, m: &dyn Encoded) {
        if let Some(index) = self.optional[opt] {
            self.log(index, t_ns, m);
        }
    }

    /// True while a client subscribes to optional channel `opt`.
    pub fn optional_wanted(&self, opt: usize) -> bool {
        self.optional[opt].is_some_and(|i| self.channels[i].has_sinks())
    }

    /// Sends an event on /events.
    pub fn event(&mut self, t_ns: u64, log: &foxglove::messages::Log) {
        self.log(self.events, t_ns, log);
    }

    /// True while a client subscribes to /scene/forces.
    pub fn forces_wanted(&self) -> bool {
        self.channels[self.scene_forces].has_sinks()
    }

    /// Sends a sample's force arrows on /scene/forces.
    pub fn forces(&mut self, t_ns: u64, arrows: &foxglove::messages::SceneUpdate) {
        self.log(self.scene_forces, t_ns, arrows);
    }

    /// Sends the wing planforms on /scene/wings to a subscribed client that has not had them
    /// yet (a client may join at any time).
    pub fn scene(&mut self, make: impl FnOnce() -> foxglove::messages::SceneUpdate, t_ns: u64) {
        let c = self.scene_wings;
        let subscribed = self.channels[c].has_sinks();
        if subscribed && !self.scene_sent {
            self.log(c, t_ns, &make());
        }
        self.scene_sent = subscribed;
    }

    /// Stops the server (clients are disconnected).
    pub fn stop(self) {
        self.server.stop().detach_all();
    }
}

impl std::fmt::Debug for LiveSink {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveSink")
            .field("port", &self.port())
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::{LiveSink, LiveWait, host_port};
    use std::time::{Duration, Instant};

    #[test]
    fn waiting_for_a_client_ends() {
        let sink = LiveSink::start(
            "127.0.0.1:0",
            &crate::options::LogOptions::default(),
            &crate::schema::WingLayout::new(2),
        )
        .unwrap();
        let short = Some(Duration::from_millis(50));
        assert_eq!(
            sink.wait_for_client(short, || false),
            LiveWait::TimedOut { connected: false }
        );
        let start = Instant::now();
        assert_eq!(sink.wait_for_client(None, || true), LiveWait::Cancelled);
        assert!(start.elapsed() < Duration::from_secs(5));
        sink.stop();
    }

    #[test]
    fn addresses() {
        assert_eq!(
            host_port("127.0.0.1:8765").unwrap(),
            ("127.0.0.1".into(), 8765)
        );
        assert_eq!(host_port("[::1]:0").unwrap(), ("::1".into(), 0));
        for bad in ["127.0.0.1", "127.0.0.1:x", ":8765", "h:70000"] {
            let e = host_port(bad).unwrap_err().to_string();
            assert!(e.contains(bad) && e.contains("HOST:PORT"), "{e}");
        }
    }
}
