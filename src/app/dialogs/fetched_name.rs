//! The name a fetched file is opened by: the server's `Content-Disposition` file name when it
//! gives one, else the address's last path segment, percent-decoded. Why: servers, object stores
//! and browsers write an MIT file's `=` as `%3D` (`motion_surface%3Dabs_shape%3Dbutter….h5`), and
//! the MIT reader reads the parameters from the name; the address as written would be refused as
//! "not key=value". Plain Rust, so that it is tested on the desktop.

use crate::app::link::percent_decode;

/// The file name for the bytes fetched from `url`, given the response's `Content-Disposition`.
pub fn file_name(url: &str, disposition: Option<&str>) -> String {
    // A name that would leave the folder it is put in is not taken.
    let usable = |name: &String| !name.is_empty() && !name.contains(['/', '\\']) && name != "..";
    disposition
        .and_then(from_disposition)
        .filter(usable)
        .or_else(|| {
            let path = url.split(['?', '#']).next()?;
            let last = path.rsplit('/').next().filter(|s| !s.is_empty())?;
            Some(percent_decode(last, false)).filter(usable)
        })
        .unwrap_or_else(|| "fetched".to_owned())
}

/// `filename*=UTF-8''…` (RFC 6266, percent-encoded) before `filename="…"` or `filename=…`.
fn from_disposition(header: &str) -> Option<String> {
    let params: Vec<(String, &str)> = header
        .split(';')
        .filter_map(|part| {
            let (key, value) = part.split_once('=')?;
            Some((key.trim().to_ascii_lowercase(), value.trim()))
        })
        .collect();
    let extended = params
        .iter()
        .find(|(k, _)| k == "filename*")
        .and_then(|(_, v)| {
            let (_charset_lang, encoded) = v.split_once("''")?;
            Some(percent_decode(encoded.trim_matches('"'), false))
        });
    extended.or_else(|| {
        params
            .iter()
            .find(|(k, _)| k == "filename")
            .map(|(_, v)| v.trim_matches('"').to_owned())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MIT: &str = "motion_surface=abs_shape=butter_a=0_v=10_i=0.000_s=0.000_t=0.000.h5";

    #[test]
    fn an_mit_file_is_named_alike_however_its_address_spells_the_equals_sign() {
        let encoded = MIT.replace('=', "%3D");
        for url in [
            format!("https://data.example/mit/{MIT}"),
            format!("https://data.example/mit/{encoded}"),
            format!("https://data.example/mit/{encoded}?download=1#x"),
        ] {
            assert_eq!(file_name(&url, None), MIT, "{url}");
        }
        // A plus in a path is a plus (only a query writes spaces as +).
        assert_eq!(file_name("https://x/a+b.csv", None), "a+b.csv");
    }

    #[test]
    fn the_servers_name_comes_first() {
        let url = "https://store.example/objects/7f3a9c";
        assert_eq!(
            file_name(url, Some(&format!("attachment; filename=\"{MIT}\""))),
            MIT
        );
        assert_eq!(
            file_name(
                url,
                Some("attachment; filename=\"x.h5\"; filename*=UTF-8''motion_surface%3Dabs.h5")
            ),
            "motion_surface=abs.h5"
        );
        assert_eq!(file_name(url, Some("inline")), "7f3a9c");
        // A name that would leave the folder is not taken.
        assert_eq!(
            file_name(url, Some("attachment; filename=\"../x\"")),
            "7f3a9c"
        );
        assert_eq!(file_name("https://x/", None), "fetched");
    }
}
