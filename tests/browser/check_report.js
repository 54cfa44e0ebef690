// Page check for `runner report` pages, run in headless Chromium by
// tests/runner/test_report_browser.cpp: after the page (and every image) has loaded, it records
// what a reader would see -- each <img> with its natural size, each cell of the figures' tables
// with the number it shows and the parameters it stands for -- as JSON in <pre id="report-check">,
// which `chromium --dump-dom` prints.
window.addEventListener('load', () => {
  const result = {
    title: document.title,
    sections: document.querySelectorAll('section.figure').length,
    notices: [...document.querySelectorAll('.notice')].map((p) => p.textContent),
    images: [...document.images].map((img) => ({
      src: img.getAttribute('src'),
      complete: img.complete,
      width: img.naturalWidth,
      height: img.naturalHeight,
    })),
    cells: [...document.querySelectorAll('table.pivot td[data-value]')].map((td) => {
      const table = td.closest('table');
      return {
        figure: table.dataset.figure,
        metric: table.dataset.metric,
        agg: table.dataset.agg,
        value: td.dataset.value,
        n: Number(td.dataset.n),
        text: td.textContent,
        params: JSON.parse(td.dataset.params),
      };
    }),
  };
  const pre = document.createElement('pre');
  pre.id = 'report-check';
  pre.textContent = JSON.stringify(result);
  document.body.appendChild(pre);
});
