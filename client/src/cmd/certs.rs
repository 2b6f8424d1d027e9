//! `luxfarm certs [--dir DIR] [--name NAME]... [--days N] [--force]`: a private certificate
//! authority and a master certificate for a farm on its own network.
//!
//! ```text
//! DIR/ca.crt + ca.key   made on the first run (ECDSA P-256, 10 years), reused afterwards
//! DIR/master.crt + master.key   a server certificate for the names given, signed by that CA
//! ```
//!
//! The master runs with `--tls-cert DIR/master.crt --tls-key DIR/master.key`; workers and
//! clients trust the CA with `--ca-cert DIR/ca.crt`. Because the CA is kept, a later run with
//! `--force` issues a certificate for more names without redistributing `ca.crt`. Private keys
//! are written with mode 0600 and never overwritten without `--force`.

use anyhow::{bail, Context};
use rcgen::{
    BasicConstraints, CertificateParams, DnType, ExtendedKeyUsagePurpose, IsCa, KeyPair,
    KeyUsagePurpose,
};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use time::{Duration, OffsetDateTime};

#[derive(clap::Args)]
pub struct Args {
    /// Folder of the CA and the master's certificate (created when missing).
    #[arg(long, default_value = "certs")]
    pub dir: PathBuf,
    /// A DNS name or IP address the master is reached by (repeatable). Default: localhost,
    /// 127.0.0.1, ::1 and this machine's host name.
    #[arg(long = "name")]
    pub names: Vec<String>,
    /// Days the master's certificate is valid.
    #[arg(long, default_value_t = 825)]
    pub days: i64,
    /// Replace an existing master certificate and key (the CA is kept).
    #[arg(long)]
    pub force: bool,
}

/// Days the CA is valid.
const CA_DAYS: i64 = 3650;

pub fn run(a: Args) -> anyhow::Result<ExitCode> {
    if !(1..=3650).contains(&a.days) {
        bail!("--days must be between 1 and 3650, got {}", a.days);
    }
    std::fs::create_dir_all(&a.dir).with_context(|| format!("creating {}", a.dir.display()))?;
    let (ca_crt, ca_key) = (a.dir.join("ca.crt"), a.dir.join("ca.key"));
    let (crt, key) = (a.dir.join("master.crt"), a.dir.join("master.key"));
    if !a.force {
        for p in [&crt, &key] {
            if p.exists() {
                bail!(
                    "{} exists: run with --force to replace the master's certificate (the CA is kept)",
                    p.display()
                );
            }
        }
    }
    let (ca, ca_pair, made) = ca(&ca_crt, &ca_key)?;
    let names = if a.names.is_empty() {
        default_names()
    } else {
        a.names.clone()
    };
    let mut params = CertificateParams::new(names.clone())
        .with_context(|| format!("not usable as certificate names: {names:?}"))?;
    params
        .distinguished_name
        .push(DnType::CommonName, names[0].clone());
    params.is_ca = IsCa::ExplicitNoCa;
    params.key_usages = vec![KeyUsagePurpose::DigitalSignature];
    params.extended_key_usages = vec![ExtendedKeyUsagePurpose::ServerAuth];
    let now = OffsetDateTime::now_utc();
    params.not_before = now - Duration::hours(1);
    params.not_after = now + Duration::days(a.days);
    let pair = KeyPair::generate().context("making the master's key")?;
    let cert = params
        .signed_by(&pair, &ca, &ca_pair)
        .context("signing the master's certificate")?;
    write_private(&key, &pair.serialize_pem())?;
    std::fs::write(&crt, cert.pem()).with_context(|| format!("writing {}", crt.display()))?;
    if made {
        println!(
            "made a new CA: {} (key {})",
            ca_crt.display(),
            ca_key.display()
        );
    } else {
        println!("kept the CA in {}", ca_crt.display());
    }
    println!(
        "master certificate for {} valid {} days: {}",
        names.join(", "),
        a.days,
        crt.display()
    );
    println!(
        "master:  luxfarm server --tls-cert {} --tls-key {} ...",
        crt.display(),
        key.display()
    );
    println!(
        "workers and clients: --master https://NAME:PORT --ca-cert {}",
        ca_crt.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// The CA in `crt`/`key`, or a new one written there; whether it was made now.
fn ca(crt: &Path, key: &Path) -> anyhow::Result<(rcgen::Certificate, KeyPair, bool)> {
    match (crt.exists(), key.exists()) {
        (true, true) => {
            let read = |p: &Path| {
                std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))
            };
            let pair = KeyPair::from_pem(&read(key)?)
                .with_context(|| format!("{} is not a PEM private key", key.display()))?;
            let params = CertificateParams::from_ca_cert_pem(&read(crt)?)
                .with_context(|| format!("{} is not a PEM CA certificate", crt.display()))?;
            // The same name and key as the file: certificates it signs chain to `crt`.
            let cert = params.self_signed(&pair).with_context(|| {
                format!("{} does not belong to {}", key.display(), crt.display())
            })?;
            Ok((cert, pair, false))
        }
        (false, false) => {
            let pair = KeyPair::generate().context("making the CA's key")?;
            let mut params = CertificateParams::new(Vec::<String>::new())?;
            params
                .distinguished_name
                .push(DnType::CommonName, "luxfarm private CA");
            params.is_ca = IsCa::Ca(BasicConstraints::Constrained(0));
            params.key_usages = vec![KeyUsagePurpose::KeyCertSign, KeyUsagePurpose::CrlSign];
            let now = OffsetDateTime::now_utc();
            params.not_before = now - Duration::hours(1);
            params.not_after = now + Duration::days(CA_DAYS);
            let cert = params.self_signed(&pair).context("making the CA")?;
            write_private(key, &pair.serialize_pem())?;
            std::fs::write(crt, cert.pem())
                .with_context(|| format!("writing {}", crt.display()))?;
            Ok((cert, pair, true))
        }
        _ => bail!(
            "only one of {} and {} exists: restore the other, or remove both to make a new CA \
             (every worker then needs the new ca.crt)",
            crt.display(),
            key.display()
        ),
    }
}

/// localhost, the loopback addresses and this machine's host name.
fn default_names() -> Vec<String> {
    let mut v = vec!["localhost".to_string(), "127.0.0.1".into(), "::1".into()];
    if let Ok(h) = std::fs::read_to_string("/etc/hostname") {
        let h = h.trim();
        if !h.is_empty() && h != "localhost" {
            v.push(h.to_string());
        }
    }
    v
}

/// Writes a private key readable by its owner only (a new file, or a replaced one).
fn write_private(path: &Path, pem: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let _ = std::fs::remove_file(path);
    let mut opts = std::fs::OpenOptions::new();
    opts.write(true).create_new(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        opts.mode(0o600);
    }
    let mut f = opts
        .open(path)
        .with_context(|| format!("writing {}", path.display()))?;
    f.write_all(pem.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}
