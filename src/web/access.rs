//! Who may read and who may command the web view (docs/decisions.md, "Web view
//! security"). Every request must name the controller in its `Host`, so that a DNS name
//! an attacker rebinds to this address reaches nothing. A write (any method but GET and
//! HEAD) must also come from the page this controller served: its `Origin` (or, without
//! one, its `Referer`) is this controller's, and it carries the controller's token, the
//! `lm_token` cookie, which only the page's own address sets (SameSite=Strict, HttpOnly).
//! On a loopback address the page hands the cookie out; with a `[web] password` the page
//! asks for it first; on any other address without a password the view is read-only.

use std::fmt;
use std::io::Read;
use std::net::{IpAddr, SocketAddr};

use axum::http::{HeaderMap, Method, header};

/// The cookie that carries the controller's token.
pub const COOKIE: &str = "lm_token";
/// Where the page sends the password.
pub const LOGIN: &str = "/api/login";

/// The web view's rules for one controller, made at start.
pub struct Access {
    /// The address the view listens on.
    bound: SocketAddr,
    /// `[web] allowed_hosts`, lower case.
    allowed_hosts: Vec<String>,
    /// The controller's secret, new at every start (hex of 32 bytes of the OS's RNG).
    token: String,
    /// `[web] password`.
    password: Option<String>,
}

/// Why a request was refused: the text of its 403 and of the log line.
#[derive(Debug, PartialEq, Eq)]
pub enum Refusal {
    ForeignHost(String),
    ReadOnly(SocketAddr),
    /// `origin`: the request's Origin (or Referer), if it has one.
    ForeignOrigin {
        origin: Option<String>,
        expected: String,
    },
    NoToken {
        login: bool,
    },
    WrongToken,
    NoPassword,
    WrongPassword,
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Refusal::ForeignHost(host) => write!(
                f,
                "refused: Host {host:?} is not this controller's address; add the name to [web] allowed_hosts to use it"
            ),
            Refusal::ReadOnly(bound) => write!(
                f,
                "read-only: the web view listens on {}, which is not loopback, and the machine file sets no [web] password",
                bound.ip()
            ),
            Refusal::ForeignOrigin { origin: Some(origin), expected } => {
                write!(f, "refused: commands come from this controller's page ({expected}), not from {origin}")
            }
            Refusal::ForeignOrigin { origin: None, expected } => {
                write!(f, "refused: commands come from this controller's page ({expected}); this one names no Origin")
            }
            Refusal::NoToken { login: true } => write!(f, "refused: no token; log in on the page first"),
            Refusal::NoToken { login: false } => {
                write!(f, "refused: no token; open the page first (it sets the {COOKIE} cookie)")
            }
            Refusal::WrongToken => write!(f, "refused: wrong token (the controller was restarted?); reload the page"),
            Refusal::NoPassword => write!(f, "refused: the machine file sets no [web] password to log in with"),
            Refusal::WrongPassword => write!(f, "refused: wrong password"),
        }
    }
}

impl Access {
    /// The rules for a view bound to `bound`, with a new token.
    pub fn new(bound: SocketAddr, web: &config::WebConfig) -> std::io::Result<Self> {
        let mut secret = [0u8; 32];
        std::fs::File::open("/dev/urandom")?.read_exact(&mut secret)?;
        let token = secret.iter().map(|b| format!("{b:02x}")).collect();
        Ok(Self::with_token(bound, web, token))
    }

    pub fn with_token(bound: SocketAddr, web: &config::WebConfig, token: String) -> Self {
        let allowed_hosts = web.allowed_hosts.iter().map(|h| h.to_ascii_lowercase()).collect();
        Access { bound, allowed_hosts, token, password: web.password.clone() }
    }

    /// Whether the view takes commands at all: on loopback, or with a password.
    pub fn writable(&self) -> bool {
        self.password.is_some() || self.bound.ip().is_loopback()
    }

    /// Whether the page logs in with the password before it gets the token.
    pub fn login(&self) -> bool {
        self.password.is_some()
    }

    /// The cookie that gives the page the token, when `GET /` hands it out: on a loopback
    /// address without a password, where whoever can reach the page could reach the
    /// Native ASCII server too.
    pub fn page_cookie(&self) -> Option<String> {
        (self.writable() && !self.login()).then(|| self.cookie())
    }

    /// `Set-Cookie` for the token.
    pub fn cookie(&self) -> String {
        format!("{COOKIE}={}; SameSite=Strict; HttpOnly; Path=/", self.token)
    }

    /// Whether `headers` carry the token (the page's state of access).
    pub fn has_token(&self, headers: &HeaderMap) -> bool {
        self.token(headers) == Ok(())
    }

    /// The password check of `POST /api/login`.
    pub fn log_in(&self, password: &str) -> Result<(), Refusal> {
        match &self.password {
            None => Err(Refusal::NoPassword),
            Some(expected) if same(expected.as_bytes(), password.as_bytes()) => Ok(()),
            Some(_) => Err(Refusal::WrongPassword),
        }
    }

    /// Every request: the `Host`; a write: also the `Origin` and the token (the login
    /// itself needs none, it is how the page gets it where there is a password).
    pub fn check(&self, method: &Method, path: &str, headers: &HeaderMap) -> Result<(), Refusal> {
        let host = text(headers, header::HOST).unwrap_or_default();
        if !self.names_us(&host) {
            return Err(Refusal::ForeignHost(host));
        }
        if method == Method::GET || method == Method::HEAD {
            return Ok(());
        }
        if !self.writable() {
            return Err(Refusal::ReadOnly(self.bound));
        }
        self.origin(&host, headers)?;
        match path {
            LOGIN if self.login() => Ok(()),
            LOGIN => Err(Refusal::NoPassword),
            _ => self.token(headers),
        }
    }

    /// Whether a `Host` value is this view: the bound address (any address of ours for
    /// 0.0.0.0 or ::, since a rebinding attack needs a name), `localhost` on such binds
    /// and on loopback, or an allowed name; with the bound port (80 when it has none).
    fn names_us(&self, host: &str) -> bool {
        let Some((name, port)) = split_host(host) else { return false };
        if port != self.bound.port() {
            return false;
        }
        let ip = self.bound.ip();
        match name.parse::<IpAddr>() {
            Ok(named) => named == ip || ip.is_unspecified(),
            Err(_) => {
                let name = name.trim_end_matches('.').to_ascii_lowercase();
                (name == "localhost" && (ip.is_loopback() || ip.is_unspecified())) || self.allowed_hosts.contains(&name)
            }
        }
    }

    /// A write's `Origin` (or `Referer`, which some clients send instead) is the page's:
    /// `http://` and the checked `Host`.
    fn origin(&self, host: &str, headers: &HeaderMap) -> Result<(), Refusal> {
        let expected = format!("http://{host}");
        let ours = match (text(headers, header::ORIGIN), text(headers, header::REFERER)) {
            (Some(origin), _) => origin.eq_ignore_ascii_case(&expected),
            (None, Some(referer)) => {
                referer.len() > expected.len()
                    && referer.is_char_boundary(expected.len())
                    && referer[..expected.len()].eq_ignore_ascii_case(&expected)
                    && referer[expected.len()..].starts_with('/')
            }
            (None, None) => false,
        };
        if ours {
            return Ok(());
        }
        let origin = text(headers, header::ORIGIN).or_else(|| text(headers, header::REFERER));
        Err(Refusal::ForeignOrigin { origin, expected })
    }

    /// The `lm_token` cookie (in any of the request's `Cookie` headers) is the token.
    fn token(&self, headers: &HeaderMap) -> Result<(), Refusal> {
        let mut offered = false;
        for value in headers.get_all(header::COOKIE) {
            let pairs = value.as_bytes().split(|&b| b == b';');
            for pair in pairs {
                let pair = pair.trim_ascii();
                let Some(value) = pair.strip_prefix(COOKIE.as_bytes()).and_then(|rest| rest.strip_prefix(b"=")) else {
                    continue;
                };
                if same(value, self.token.as_bytes()) {
                    return Ok(());
                }
                offered = true;
            }
        }
        Err(if offered { Refusal::WrongToken } else { Refusal::NoToken { login: self.login() } })
    }
}

/// A header as text (what is not UTF-8 shown as such).
fn text(headers: &HeaderMap, name: header::HeaderName) -> Option<String> {
    headers.get(name).map(|value| String::from_utf8_lossy(value.as_bytes()).into_owned())
}

/// `name:port`, `[v6]:port` or a name alone (port 80).
fn split_host(host: &str) -> Option<(&str, u16)> {
    let (name, port) = match host.strip_prefix('[') {
        Some(rest) => match rest.split_once(']')? {
            (name, "") => (name, "80"),
            (name, after) => (name, after.strip_prefix(':')?),
        },
        None => host.rsplit_once(':').unwrap_or((host, "80")),
    };
    if name.is_empty() {
        return None;
    }
    Some((name, port.parse().ok()?))
}

/// Compares secrets in a time that does not depend on where they differ.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |differ, (x, y)| differ | (x ^ y)) == 0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `web`: an allowed host name or `password=...`, or nothing.
    fn access(bound: &str, web: &str) -> Access {
        let web = match web.strip_prefix("password=") {
            Some(password) => config::WebConfig { password: Some(password.into()), ..Default::default() },
            None if web.is_empty() => config::WebConfig::default(),
            None => config::WebConfig { allowed_hosts: vec![web.into()], ..Default::default() },
        };
        Access::with_token(bound.parse().unwrap(), &web, "t0k3n".into())
    }

    fn headers(pairs: &[(&'static str, &str)]) -> HeaderMap {
        let mut map = HeaderMap::new();
        for (name, value) in pairs {
            map.append(*name, value.parse().unwrap());
        }
        map
    }

    /// Which `Host` names the view, by bind: the address itself, `localhost` on loopback
    /// and on 0.0.0.0, allowed names in any case, always with the bound port.
    #[test]
    fn the_host_must_name_this_controller() {
        let table = [
            ("127.0.0.1:8080", "", "127.0.0.1:8080", true),
            ("127.0.0.1:8080", "", "localhost:8080", true),
            ("127.0.0.1:8080", "", "LocalHost.:8080", true),
            ("127.0.0.1:8080", "", "127.0.0.1:8081", false),
            ("127.0.0.1:8080", "", "127.0.0.1", false),
            ("127.0.0.1:8080", "", "rebind.evil.example:8080", false),
            ("127.0.0.1:8080", "", "", false),
            ("127.0.0.1:8080", "", ":8080", false),
            ("127.0.0.1:8080", "", "127.0.0.1:8080:8080", false),
            ("127.0.0.1:80", "", "127.0.0.1", true),
            ("[::1]:8080", "", "[::1]:8080", true),
            ("[::1]:8080", "", "[::1]x:8080", false),
            ("[::1]:8080", "", "localhost:8080", true),
            ("192.168.1.5:8080", "", "192.168.1.5:8080", true),
            ("192.168.1.5:8080", "", "localhost:8080", false),
            ("192.168.1.5:8080", "", "10.0.0.7:8080", false),
            ("192.168.1.5:8080", "Cell-7.local", "cell-7.LOCAL:8080", true),
            ("192.168.1.5:8080", "cell-7.local", "cell-8.local:8080", false),
            ("0.0.0.0:8080", "", "10.0.0.7:8080", true),
            ("0.0.0.0:8080", "", "localhost:8080", true),
            ("0.0.0.0:8080", "", "plant.example:8080", false),
        ];
        for (bound, web, host, ours) in table {
            assert_eq!(access(bound, web).names_us(host), ours, "bound {bound} {web}, Host {host:?}");
        }
    }

    /// Who may write: loopback (127.0.0.0/8 and ::1) without a password, any address
    /// with one; 0.0.0.0 and the LAN's addresses without one are read-only, every write
    /// refused before its token is looked at.
    #[test]
    fn a_bind_other_than_loopback_without_a_password_is_read_only() {
        let table = [
            ("127.0.0.1:8080", "", true, true),
            ("127.0.0.2:8080", "", true, true),
            ("[::1]:8080", "", true, true),
            ("0.0.0.0:8080", "", false, false),
            ("[::]:8080", "", false, false),
            ("192.168.1.5:8080", "", false, false),
            ("192.168.1.5:8080", "password=pw", true, false),
            ("127.0.0.1:8080", "password=pw", true, false),
        ];
        for (bound, web, writable, hands_out) in table {
            let access = access(bound, web);
            assert_eq!((access.writable(), access.page_cookie().is_some()), (writable, hands_out), "{bound} {web}");
            let host = access.bound.to_string();
            let origin = format!("http://{host}");
            let request = headers(&[("host", &host), ("origin", &origin), ("cookie", "lm_token=t0k3n")]);
            let outcome = access.check(&Method::POST, "/api/axis/0/enable", &request);
            assert_eq!(outcome.is_ok(), writable, "{bound} {web}: {outcome:?}");
            if !writable {
                assert!(outcome.unwrap_err().to_string().starts_with("read-only: "));
            }
        }
    }

    /// A write needs the page's Origin (or Referer) and the token cookie; each refusal
    /// says which.
    #[test]
    fn a_write_needs_the_pages_origin_and_token() {
        let access = access("127.0.0.1:8080", "");
        let check = |pairs: &[(&'static str, &str)]| access.check(&Method::POST, "/api/drl/open-run", &headers(pairs));
        let host = ("host", "127.0.0.1:8080");
        let token = ("cookie", "other=1; lm_token=t0k3n");
        assert_eq!(check(&[host, ("origin", "http://127.0.0.1:8080"), token]), Ok(()));
        assert_eq!(check(&[host, ("referer", "http://127.0.0.1:8080/"), token]), Ok(()));
        assert_eq!(check(&[("host", "localhost:8080"), ("origin", "http://localhost:8080"), token]), Ok(()));
        assert_eq!(
            check(&[host, ("cookie", "a=b"), ("cookie", "lm_token=t0k3n"), ("origin", "http://127.0.0.1:8080")]),
            Ok(())
        );
        let foreign = |r: Result<(), Refusal>| matches!(r, Err(Refusal::ForeignOrigin { .. }));
        assert!(foreign(check(&[host, ("origin", "http://attacker.example"), token])));
        assert!(foreign(check(&[host, ("origin", "null"), token])));
        assert!(foreign(check(&[host, ("origin", "http://localhost:8080"), token])), "another name of ours");
        assert!(foreign(check(&[host, ("referer", "http://127.0.0.1:8080.evil.example/"), token])));
        assert!(foreign(check(&[host, token])), "no Origin at all");
        let origin = ("origin", "http://127.0.0.1:8080");
        assert_eq!(check(&[host, origin]), Err(Refusal::NoToken { login: false }));
        assert_eq!(check(&[host, origin, ("cookie", "lm_token=t0k3m")]), Err(Refusal::WrongToken));
        assert_eq!(check(&[host, origin, ("cookie", "lm_token=")]), Err(Refusal::WrongToken));
        assert_eq!(check(&[host, origin, ("cookie", "xlm_token=t0k3n")]), Err(Refusal::NoToken { login: false }));
        assert!(matches!(check(&[("host", "rebind.evil.example:8080"), origin, token]), Err(Refusal::ForeignHost(_))));
        assert_eq!(access.check(&Method::PUT, "/", &headers(&[host, origin])), Err(Refusal::NoToken { login: false }));
        assert_eq!(access.check(&Method::GET, "/api/state", &headers(&[host])), Ok(()));
    }

    /// The login takes only the configured password; with none there is nothing to log in to.
    #[test]
    fn the_login_takes_the_password() {
        assert_eq!(access("192.168.1.5:8080", "password=pw").log_in("pw"), Ok(()));
        assert_eq!(access("192.168.1.5:8080", "password=pw").log_in("pW"), Err(Refusal::WrongPassword));
        assert_eq!(access("192.168.1.5:8080", "password=pw").log_in(""), Err(Refusal::WrongPassword));
        assert_eq!(access("127.0.0.1:8080", "").log_in("pw"), Err(Refusal::NoPassword));
    }
}
